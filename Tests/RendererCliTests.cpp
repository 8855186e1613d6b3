// jawari-render end to end: good scenes write complete files, bad ones exit with status 2, name the
// field and leave nothing behind.

#include "RendererCliSupport.h"
#include "TestSupport.h"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using jawari::test::render;
using jawari::test::scratch;
using jawari::test::write;

TEST_CASE("jawari-render writes a WAV and an energy log for a good scene")
{
    const auto dir = scratch();
    const auto wav = dir / "centre.wav";
    const auto csv = dir / "centre.csv";
    const auto o = render(jawari::test::resource("Scenes/paper-centre.json") + " -o " + wav.string()
                          + " --duration 0.02 --rate 1e6 --modes 400 --raw --energy " + csv.string());
    INFO(o.output);
    REQUIRE(o.status == 0);
    REQUIRE(fs::exists(wav));
    // RIFF/WAVE, 32-bit float, 960 samples of data.
    CHECK(fs::file_size(wav) >= 44 + 960 * 4);
    std::ifstream in(wav, std::ios::binary);
    char riff[4];
    in.read(riff, 4);
    CHECK(std::string(riff, 4) == "RIFF");
    std::ifstream log(csv);
    std::string line;
    int rows = -1;
    while (std::getline(log, line))
        ++rows;
    CHECK(rows == 960);
    CHECK_THAT(o.output, Catch::Matchers::Contains("400 modes"));
}

TEST_CASE("jawari-render rejects bad scenes and options with status 2 and writes nothing")
{
    const auto dir = scratch();
    const auto wav = dir / "never.wav";
    struct Case
    {
        std::string scene, extra, expected;
    };
    const std::vector<Case> cases = {
        {R"({"format": "jawari-scene/1", "string": {"length": -1}})", "", "string.length"},
        {R"({"format": "jawari-scene/1", "obstacles": [{"position": 2}]})", "", "obstacles[0].position"},
        {R"({"format": "jawari-scene/1", "pickup": {"position": 0}})", "", "pickup.position"},
        {R"({"format": "jawari-scene/1", "excitation": {"position": 5}})", "", "excitation.position"},
        {R"({"format": "jawari-scene/1", "simulation": {"bogus": 1}})", "", "simulation.bogus"},
        {R"({"format": "jawari-scene/1", )", "", "malformed JSON"},
        {R"({"format": "jawari-scene/1"})", "--rate abc", "--rate"},
        {R"({"format": "jawari-scene/1"})", "--duration -2", "simulation.duration"},
        {R"({"format": "jawari-scene/1"})", "--method magic", "--method"},
        {R"({"format": "jawari-scene/1"})", "--frobnicate", "unknown option"},
    };
    int i = 0;
    for (const auto& c : cases)
    {
        const auto scene = write(dir / ("bad" + std::to_string(i++) + ".json"), c.scene);
        const auto o = render(scene + " -o " + wav.string() + " " + c.extra);
        INFO(c.scene << " " << c.extra << "\n" << o.output);
        CHECK(o.status == 2);
        CHECK_THAT(o.output, Catch::Matchers::Contains(c.expected));
        CHECK_FALSE(fs::exists(wav));
    }
    const auto missing = render((dir / "does-not-exist.json").string() + " -o " + wav.string());
    CHECK(missing.status == 2);
    CHECK_FALSE(fs::exists(wav));
    const auto none = render("-o " + wav.string());
    CHECK(none.status == 2);
}

TEST_CASE("a bad render leaves an existing output file untouched")
{
    const auto dir = scratch();
    const auto wav = dir / "keep.wav";
    write(wav, "previous contents");
    const auto scene = write(dir / "bad.json", R"({"format": "jawari-scene/1", "obstacles": [{"stiffness": 0}]})");
    const auto o = render(scene + " -o " + wav.string());
    CHECK(o.status == 2);
    std::ifstream in(wav);
    std::string text;
    std::getline(in, text);
    CHECK(text == "previous contents");
}

TEST_CASE("jawari-render warns when the initial shape starts inside an obstacle and still renders")
{
    const auto dir = scratch();
    const auto wav = dir / "inside.wav";
    const auto o =
        render(jawari::test::resource("../Tests/scenes/corpus/render-pushed-1cm-in.json") + " -o " + wav.string());
    INFO(o.output);
    CHECK(o.status == 0);
    CHECK(fs::exists(wav));
    CHECK_THAT(o.output, Catch::Matchers::Contains("warning: the initial shape starts inside an obstacle"));
    const auto quietRun =
        render(jawari::test::resource("Scenes/paper-centre.json") + " -o " + wav.string() + " --duration 0.01");
    CHECK_THAT(quietRun.output, !Catch::Matchers::Contains("warning"));
}
