// jawari-render end to end: good scenes write complete files (24-bit or float), bad ones exit with
// status 2, name the field and leave nothing behind.

#include "RendererCliSupport.h"
#include "TestSupport.h"

#include <catch2/catch.hpp>

#include <juce_audio_formats/juce_audio_formats.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <regex>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using jawari::test::render;
using jawari::test::scratch;
using jawari::test::write;

namespace
{
struct MonoWav
{
    int bits = 0;
    std::vector<float> samples;
};

MonoWav readMono(const fs::path& path)
{
    juce::WavAudioFormat format;
    std::unique_ptr<juce::AudioFormatReader> reader(
        format.createReaderFor(new juce::FileInputStream(juce::File(path.string())), true));
    REQUIRE(reader != nullptr);
    REQUIRE(reader->numChannels == 1);
    juce::AudioBuffer<float> buffer(1, int(reader->lengthInSamples));
    REQUIRE(reader->read(&buffer, 0, buffer.getNumSamples(), 0, true, false));
    const float* data = buffer.getReadPointer(0);
    return {int(reader->bitsPerSample), std::vector<float>(data, data + buffer.getNumSamples())};
}

double peakOf(const std::vector<float>& samples)
{
    double peak = 0.0;
    for (const float x : samples)
        peak = std::max(peak, double(std::abs(x)));
    return peak;
}
}  // namespace

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
        {R"({"format": "jawari-scene/1"})", "--format mp3", "--format: unknown format 'mp3' (expected int24 or float)"},
        {R"({"format": "jawari-scene/1"})", "--raw --format int24", "--raw writes SI units, which only --format float"},
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

TEST_CASE("jawari-render --format: a scene as 24-bit or float at -1 dBFS, and --raw keeps values above 1")
{
    // A 5 mm pluck read as velocity: the string's points move at c x 2A/L (c = 393 m/s), about 4 m/s.
    const auto dir = scratch();
    const auto scene = write(dir / "fast.json", R"({"format": "jawari-scene/1", "excitation": {"amplitude": 0.005},
        "pickup": {"quantity": "velocity"}, "simulation": {"method": "realtime", "duration": 0.05}})");
    const auto int24 = dir / "fast24.wav", ieee = dir / "fast-float.wav", raw = dir / "fast-raw.wav";
    const auto a = render(scene + " -o " + int24.string());
    const auto b = render(scene + " --format float -o " + ieee.string());
    const auto c = render(scene + " --raw -o " + raw.string());
    INFO(a.output << "\n" << b.output << "\n" << c.output);
    REQUIRE(a.status == 0);
    REQUIRE(b.status == 0);
    REQUIRE(c.status == 0);
    CHECK_THAT(a.output, Catch::Matchers::Contains("(24-bit, -1 dBFS peak)"));
    CHECK_THAT(b.output, Catch::Matchers::Contains("(32-bit float, -1 dBFS peak)"));
    CHECK_THAT(c.output, Catch::Matchers::Contains("(32-bit float, SI units)"));

    const auto w24 = readMono(int24), wf = readMono(ieee), wr = readMono(raw);
    CHECK(w24.bits == 24);
    CHECK(wf.bits == 32);
    CHECK(wr.bits == 32);
    REQUIRE(w24.samples.size() == 2400);
    REQUIRE(wf.samples.size() == 2400);
    REQUIRE(wr.samples.size() == 2400);
    const double full = std::pow(10.0, -1.0 / 20.0);
    CHECK(peakOf(wf.samples) == Approx(full).epsilon(1e-6));
    double worst = 0.0;
    for (size_t i = 0; i < w24.samples.size(); ++i)
        worst = std::max(worst, double(std::abs(w24.samples[i] - wf.samples[i])));
    CHECK(worst <= 1.0 / 8388608.0);

    // The raw file holds the velocity as computed: above 1 m/s, the summary's peak to its 6 digits.
    std::smatch m;
    REQUIRE(std::regex_search(c.output, m, std::regex(R"(peak ([0-9.e+-]+) m/s velocity)")));
    const double rawPeak = peakOf(wr.samples);
    INFO("raw peak " << rawPeak << " m/s");
    CHECK(rawPeak > 2.0);
    CHECK(rawPeak == Approx(std::stod(m[1])).epsilon(1e-5));
    CHECK_THAT(c.output, !Catch::Matchers::Contains("full scale"));
}
