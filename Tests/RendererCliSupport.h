#pragma once
// Running the built jawari-render from the tests: its exit status and everything it printed.

#include <catch2/catch.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace jawari::test
{

struct Outcome
{
    int status = -1;
    std::string output;  // stdout and stderr
};

inline Outcome render(const std::string& arguments)
{
    const std::string command = std::string(JAWARI_RENDER_PATH) + " " + arguments + " 2>&1";
    Outcome o;
    FILE* pipe = popen(command.c_str(), "r");
    REQUIRE(pipe != nullptr);
    char buffer[512];
    while (std::fgets(buffer, sizeof buffer, pipe) != nullptr)
        o.output += buffer;
    const int raw = pclose(pipe);
    o.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    return o;
}

// A folder of this test run's own, removed with everything in it when the test program exits.
class ScratchFolder
{
public:
    ScratchFolder()
        : dir_(std::filesystem::temp_directory_path() / ("jawari-cli-" + std::to_string(::getpid())))
    {
        std::filesystem::create_directories(dir_);
    }
    ~ScratchFolder()
    {
        std::error_code ignored;  // a folder that cannot be removed is left, never a throw at exit
        std::filesystem::remove_all(dir_, ignored);
    }
    ScratchFolder(const ScratchFolder&) = delete;
    ScratchFolder& operator=(const ScratchFolder&) = delete;
    const std::filesystem::path& path() const { return dir_; }

private:
    std::filesystem::path dir_;
};

inline std::filesystem::path scratch()
{
    static const ScratchFolder folder;
    std::filesystem::create_directories(folder.path());  // a test may have emptied it
    return folder.path();
}

inline std::string write(const std::filesystem::path& path, const std::string& text)
{
    std::ofstream(path, std::ios::binary) << text;
    return path.string();
}

}  // namespace jawari::test
