// jawari-render --midi end to end: MIDI files written here with juce::MidiFile, rendered by the
// binary, read back with JUCE's WAV reader and measured (the pitch of a held note, an onset after a
// tempo change, the length, the silence-terminated tail, the samples of the AudioProcessor played
// in-process, as 24-bit and as float, and the report of a 24-bit file that clips); bad files,
// presets, states and option mixes exit with status 2 and write nothing.

#include "MidiFileSupport.h"
#include "PluginProcessor.h"
#include "Presets.h"
#include "RendererCliSupport.h"
#include "TestSupport.h"
#include "offline/Analysis.h"

#include <catch2/catch.hpp>

#include <juce_audio_formats/juce_audio_formats.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <random>
#include <regex>
#include <string>
#include <utility>
#include <vector>

namespace fs = std::filesystem;
using jawari::test::render;
using jawari::test::scratch;
using jawari::test::track;
using jawari::test::write;

namespace
{
constexpr int kTicksPerQuarter = 480;  // 120 bpm until a tempo event says otherwise: 960 ticks a second

std::string writeMidi(const fs::path& path, const std::vector<juce::MidiMessageSequence>& tracks, int type)
{
    REQUIRE(jawari::test::writeMidiFile(juce::File(path.string()), tracks, type, kTicksPerQuarter));
    return path.string();
}

// A3 (220 Hz) at velocity 100 from 0 to 1 s, in a type 0 file.
std::string heldA3(const fs::path& path)
{
    return writeMidi(
        path,
        {track({{0, juce::MidiMessage::noteOn(1, 57, juce::uint8(100))}, {960, juce::MidiMessage::noteOff(1, 57)}})},
        0);
}

struct Wav
{
    int channels = 0, bits = 0;
    double rate = 0.0;
    std::vector<double> left, right;
};

Wav readWav(const fs::path& path)
{
    juce::WavAudioFormat format;
    std::unique_ptr<juce::AudioFormatReader> reader(
        format.createReaderFor(new juce::FileInputStream(juce::File(path.string())), true));
    REQUIRE(reader != nullptr);
    Wav w;
    w.channels = int(reader->numChannels);
    w.bits = int(reader->bitsPerSample);
    w.rate = reader->sampleRate;
    juce::AudioBuffer<float> buffer(w.channels, int(reader->lengthInSamples));
    REQUIRE(reader->read(&buffer, 0, buffer.getNumSamples(), 0, true, true));
    for (int i = 0; i < buffer.getNumSamples(); ++i)
    {
        w.left.push_back(buffer.getSample(0, i));
        w.right.push_back(buffer.getSample(w.channels - 1, i));
    }
    return w;
}

double peakOf(const Wav& w)
{
    double m = 0.0;
    for (size_t i = 0; i < w.left.size(); ++i)
        m = std::max({m, std::abs(w.left[i]), std::abs(w.right[i])});
    return m;
}

// The first sample whose level reaches `level` (the size when none does).
size_t onset(const std::vector<double>& y, double level)
{
    const auto it = std::find_if(y.begin(), y.end(), [level](double v) { return std::abs(v) >= level; });
    return size_t(it - y.begin());
}
struct Rendered
{
    std::string output;
    Wav wav;
};

using Script = std::vector<std::pair<double, juce::MidiMessage>>;  // (seconds, message)

// A script as a type 0 file (at 120 bpm, 960 ticks a second).
std::string writeScript(const fs::path& path, const Script& script)
{
    juce::MidiMessageSequence events;
    for (auto [seconds, message] : script)
    {
        message.setTimeStamp(seconds * 960.0);
        events.addEvent(message);
    }
    return writeMidi(path, {events}, 0);
}

struct Stereo
{
    std::vector<double> left, right;
};

// The processor's own output for a script, `seconds` long, played in-process as the renderer plays
// it: prepared at 48 kHz, 512-sample blocks, each event at its sample, the latency removed.
Stereo renderInProcess(jawari::plugin::JawariAudioProcessor& p, const Script& script, double seconds)
{
    const double rate = 48000.0;
    const int block = 512;
    p.setNonRealtime(true);
    p.setPlayConfigDetails(0, 2, rate, block);
    p.prepareToPlay(rate, block);
    REQUIRE(p.waitForBuilds());
    const auto latency = size_t(p.getLatencySamples());
    const auto total = size_t(std::lround(seconds * rate)) + latency;
    Stereo out;
    juce::AudioBuffer<float> buffer(2, block);
    for (long start = 0; out.left.size() < total; start += block)
    {
        juce::MidiBuffer midi;
        for (const auto& [at, message] : script)
            if (const long sample = std::lround(at * rate); sample >= start && sample < start + block)
                midi.addEvent(message, int(sample - start));
        buffer.clear();
        p.processBlock(buffer, midi);
        for (int i = 0; i < block; ++i)
        {
            out.left.push_back(buffer.getSample(0, i));
            out.right.push_back(buffer.getSample(1, i));
        }
    }
    for (auto* channel : {&out.left, &out.right})
    {
        channel->erase(channel->begin(), channel->begin() + long(latency));
        channel->resize(total - latency);
    }
    return out;
}

// The largest difference between a file's samples and the processor's (the lengths must agree).
double largestDifference(const Wav& w, const Stereo& s)
{
    REQUIRE(w.left.size() == s.left.size());
    double worst = 0.0;
    for (size_t i = 0; i < w.left.size(); ++i)
        worst = std::max({worst, std::abs(w.left[i] - s.left[i]), std::abs(w.right[i] - s.right[i])});
    return worst;
}

// The held A3 rendered with `options` into `name`.wav.
Rendered renderHeldA3(const std::string& name, const std::string& options)
{
    const auto dir = scratch();
    const auto wav = dir / (name + ".wav");
    const auto o = render("--midi " + heldA3(dir / (name + ".mid")) + " " + options + " -o " + wav.string());
    INFO(o.output);
    REQUIRE(o.status == 0);
    return {o.output, readWav(wav)};
}

// A 24-bit file against the processor's samples: the largest difference where they lie within full
// scale, and where they reach it or beyond (against the rail, +-1).
std::pair<double, double> differencesInsideAndOnRail(const Wav& w, const Stereo& s)
{
    REQUIRE(w.left.size() == s.left.size());
    double inside = 0.0, rail = 0.0;
    for (size_t i = 0; i < w.left.size(); ++i)
        for (const auto& [x, y] : {std::pair{s.left[i], w.left[i]}, std::pair{s.right[i], w.right[i]}})
            if (std::abs(x) >= 1.0)
                rail = std::max(rail, std::abs(std::clamp(x, -1.0, 1.0) - y));
            else
                inside = std::max(inside, std::abs(x - y));
    return {inside, rail};
}
}  // namespace

TEST_CASE("jawari-render --midi plays a held A3 in tune with the Default preset, as stereo 24-bit")
{
    const auto [output, w] = renderHeldA3("a3", "--preset Default");
    CHECK_THAT(output, Catch::Matchers::Contains("preset 'Default (tanpura bridge, no drone)'"));
    CHECK(w.channels == 2);
    CHECK(w.bits == 24);
    CHECK(w.rate == 48000.0);
    const double f0 = jawari::peakFrequency(w.left, w.rate, 200.0, 240.0, 4800, 38400);  // 0.1 .. 0.9 s
    INFO("f0 " << f0 << " Hz, peak " << peakOf(w));
    CHECK(std::abs(f0 / 220.0 - 1.0) < 0.005);
    CHECK(peakOf(w) > 0.05);
    CHECK(peakOf(w) < 1.0);
    CHECK_THAT(output, !Catch::Matchers::Contains("full scale") && !Catch::Matchers::Contains("warning"));
}

TEST_CASE("jawari-render --midi: a note after a tempo change in another track starts at its time (type 1)")
{
    // The conductor track: 120 bpm, then 60 bpm from tick 960 (1.0 s). The note at tick 1440 is a
    // beat later, at 2.0 s (1.5 s if the change were ignored); its note-off a beat after that.
    const auto dir = scratch();
    const auto wav = dir / "tempo.wav";
    const auto conductor =
        track({{0, juce::MidiMessage::tempoMetaEvent(500000)}, {960, juce::MidiMessage::tempoMetaEvent(1000000)}});
    const auto notes =
        track({{1440, juce::MidiMessage::noteOn(2, 57, juce::uint8(100))}, {1920, juce::MidiMessage::noteOff(2, 57)}});
    const auto o = render("--midi " + writeMidi(dir / "tempo.mid", {conductor, notes}, 1) + " -o " + wav.string());
    INFO(o.output);
    REQUIRE(o.status == 0);
    CHECK_THAT(o.output, Catch::Matchers::Contains("MIDI type 1, 2 tracks, 2 events, the last at 3.000 s"));
    const auto w = readWav(wav);
    const size_t start = onset(w.left, 1e-4);
    INFO("onset at sample " << start << " (" << double(start) / w.rate << " s)");
    CHECK(std::abs(double(start) - 96000.0) <= 96.0);  // within 2 ms of 2.0 s
}

TEST_CASE("jawari-render --midi --duration writes exactly that many stereo samples at --output-rate")
{
    const auto [output, w] = renderHeldA3("short", "--duration 0.75 --output-rate 44100 --quiet");
    CHECK(output.empty());
    CHECK(w.channels == 2);
    CHECK(w.rate == 44100.0);
    CHECK(w.left.size() == 33075);
    CHECK(std::abs(jawari::peakFrequency(w.left, w.rate, 200.0, 240.0, 4410, 22050) / 220.0 - 1.0) < 0.005);
}

TEST_CASE("jawari-render --midi ends the file after 0.5 s below -100 dBFS past the last event, or at the cap")
{
    const auto w = renderHeldA3("tail", "").wav;
    const size_t n = w.left.size(), hold = 24000;  // 0.5 s
    REQUIRE(n > 48000 + hold);
    double lastHalfSecond = 0.0;
    for (size_t i = n - hold; i < n; ++i)
        lastHalfSecond = std::max({lastHalfSecond, std::abs(w.left[i]), std::abs(w.right[i])});
    const double justBefore = std::max(std::abs(w.left[n - hold - 1]), std::abs(w.right[n - hold - 1]));
    INFO("length " << double(n) / w.rate << " s; last 0.5 s peak " << lastHalfSecond << ", the sample before "
                   << justBefore);
    const double step = 1.0 / 8388608.0;  // the renderer compares before the 24-bit rounding
    CHECK(lastHalfSecond < 1e-5 + step);
    CHECK(justBefore >= 1e-5 - step);
    // Released at 1 s (60 dB in the 0.4 s release), silent well within two seconds of it.
    CHECK(double(n) / w.rate < 3.0);

    // The drone never falls silent: the render stops 60 s after the last event and says so.
    const auto dir = scratch();
    const auto wav = dir / "drone-cap.wav";
    const auto cc = writeMidi(dir / "cc.mid", {track({{0, juce::MidiMessage::controllerEvent(1, 7, 100)}})}, 0);
    const auto drone = render("--midi " + cc + " --preset 'Tanpura drone' -o " + wav.string());
    INFO(drone.output);
    REQUIRE(drone.status == 0);
    CHECK_THAT(drone.output, Catch::Matchers::Contains("note: the output was still above -100 dBFS 60 s"));
    const auto d = readWav(wav);
    CHECK(d.left.size() == 60 * 48000);
    CHECK(peakOf(d) > 0.05);
}

TEST_CASE("jawari-render --midi writes the samples the AudioProcessor gives in-process, as 24-bit and as float")
{
    // Bend, sustain over a note-off, a second note, the pedal up and all-notes-off, each at its
    // sample; in-process the events go straight into 512-sample blocks (the renderer's block size).
    const Script script = {
        {0.0, juce::MidiMessage::noteOn(1, 57, juce::uint8(100))},
        {0.25, juce::MidiMessage::pitchWheel(1, 12000)},
        {0.3, juce::MidiMessage::controllerEvent(1, 64, 127)},
        {0.4, juce::MidiMessage::noteOff(1, 57)},
        {0.5, juce::MidiMessage::noteOn(1, 64, juce::uint8(90))},
        {0.7, juce::MidiMessage::controllerEvent(1, 64, 0)},
        {0.9, juce::MidiMessage::allNotesOff(1)},
    };
    const auto dir = scratch();
    const auto midi = writeScript(dir / "script.mid", script);
    const auto int24 = dir / "script.wav", ieee = dir / "script-float.wav";
    const auto a = render("--midi " + midi + " --duration 1.2 -o " + int24.string());
    const auto b = render("--midi " + midi + " --duration 1.2 --format float -o " + ieee.string());
    INFO(a.output << "\n" << b.output);
    REQUIRE(a.status == 0);
    REQUIRE(b.status == 0);
    CHECK_THAT(b.output, Catch::Matchers::Contains("stereo 32-bit float, peak -"));
    const auto w24 = readWav(int24), wf = readWav(ieee);
    CHECK(w24.bits == 24);
    CHECK(wf.bits == 32);

    jawari::plugin::JawariAudioProcessor p;
    const auto played = renderInProcess(p, script, 1.2);
    double peak = 0.0;
    for (const double x : played.left)
        peak = std::max(peak, std::abs(x));
    const double worst24 = largestDifference(w24, played), worstFloat = largestDifference(wf, played);
    INFO("peak " << peak << ", largest difference: 24-bit " << worst24 << ", float " << worstFloat);
    CHECK(peak > 0.05);
    CHECK(worst24 <= 1.0 / 8388608.0);  // one step of 24 bits
    CHECK(worstFloat == 0.0);
}

TEST_CASE("jawari-render --midi: a 24-bit file that clips says how many samples and the true peak; float keeps "
          "them")
{
    // Eight notes struck together at full velocity, a fourth apart from E2, through the Bass fret
    // buzz preset at +6 dB of Output gain (saved as the plugin saves a state).
    const auto dir = scratch();
    Script chord;
    for (int note = 40; note < 40 + 8 * 5; note += 5)
    {
        chord.push_back({0.0, juce::MidiMessage::noteOn(1, note, juce::uint8(127))});
        chord.push_back({1.0, juce::MidiMessage::noteOff(1, note)});
    }
    const auto midi = writeScript(dir / "fortissimo.mid", chord);
    const auto state = dir / "bass-6db.jawaripreset";
    {
        jawari::plugin::JawariAudioProcessor p;
        p.setCurrentProgram(jawari::plugin::factoryPresetByShortName("Bass fret buzz"));
        auto* gain = p.parameters().getParameter(jawari::plugin::ids::gain);
        gain->setValueNotifyingHost(gain->convertTo0to1(6.0f));
        REQUIRE(p.state().createXml()->writeTo(juce::File(state.string())));
    }
    const std::string options = "--midi " + midi + " --state " + state.string() + " --duration 1.5 ";
    const auto int24 = dir / "fortissimo.wav", ieee = dir / "fortissimo-float.wav";
    const auto a = render(options + "-o " + int24.string());
    const auto b = render(options + "--format float -o " + ieee.string());
    const auto quiet = render(options + "--quiet -o " + (dir / "fortissimo-quiet.wav").string());
    INFO(a.output << "\n" << b.output);
    REQUIRE(a.status == 0);  // a warning, not a failure
    REQUIRE(b.status == 0);
    REQUIRE(quiet.status == 0);

    // The processor's samples, exactly, in the float file: those beyond full scale too.
    jawari::plugin::JawariAudioProcessor p;
    REQUIRE(p.loadUserPreset(juce::File(state.string())).wasOk());
    const auto played = renderInProcess(p, chord, 1.5);
    const auto wf = readWav(ieee), w24 = readWav(int24);
    CHECK(largestDifference(wf, played) == 0.0);
    long long over = 0;
    for (const auto* channel : {&wf.left, &wf.right})
        over += std::count_if(channel->begin(), channel->end(), [](double x) { return std::abs(x) >= 1.0; });
    const double peak = peakOf(wf), peakDb = 20.0 * std::log10(peak);
    INFO(over << " samples at or beyond full scale, peak " << peak);
    REQUIRE(over > 0);

    // The summary gives that count and that peak; the warning says it again, with the remedy.
    std::smatch m;
    const std::regex summary(R"(peak ([-+0-9.]+) dBFS, ([0-9]+) samples at or beyond full scale clipped)");
    REQUIRE(std::regex_search(a.output, m, summary));
    CHECK(std::stoll(m[2]) == over);
    CHECK(std::abs(std::stod(m[1]) - peakDb) <= (peak > 1.0 ? 0.005 : 0.05));
    const std::string counted = std::to_string(over) + " samples at";
    CHECK_THAT(a.output, Catch::Matchers::Contains("warning: the 24-bit file") && Catch::Matchers::Contains(counted));
    CHECK_THAT(a.output, Catch::Matchers::Contains(peak > 1.0 ? "write --format float, which keeps every sample"
                                                              : "the plugin gave them already limited to +-1"));
    // --quiet drops the summary, not the warning.
    CHECK(quiet.output.rfind("warning: the 24-bit file", 0) == 0);
    CHECK_THAT(quiet.output, !Catch::Matchers::Contains("wrote"));
    // The float file: the same count, kept, and no warning.
    const std::string kept = std::to_string(over) + " samples at or beyond full scale kept as given";
    CHECK_THAT(b.output, Catch::Matchers::Contains(kept));
    CHECK_THAT(b.output, !Catch::Matchers::Contains("warning"));

    // The 24-bit file: on the rail where the processor reached full scale, within a step elsewhere.
    const auto [worstInside, worstRail] = differencesInsideAndOnRail(w24, played);
    INFO("24-bit against the processor: " << worstInside << " within full scale, " << worstRail << " on the rail");
    CHECK(worstInside <= 1.0 / 8388608.0);
    CHECK(worstRail <= 1.0 / 8388608.0);
}

TEST_CASE("jawari-render --midi plays a state file the plugin saved, and factory presets by their short names")
{
    const auto dir = scratch();
    jawari::plugin::JawariAudioProcessor p;
    auto* gain = p.parameters().getParameter(jawari::plugin::ids::gain);
    gain->setValueNotifyingHost(gain->convertTo0to1(-6.0f));
    const auto state = dir / "quieter.jawaripreset";
    REQUIRE(p.state().createXml()->writeTo(juce::File(state.string())));
    const auto plain = renderHeldA3("plain", "--quiet");
    const auto quieter = renderHeldA3("quieter", "--state " + state.string());
    CHECK_THAT(quieter.output, Catch::Matchers::Contains("state 'quieter.jawaripreset'"));
    const double ratio = peakOf(quieter.wav) / peakOf(plain.wav);
    INFO("peak ratio " << ratio);
    CHECK(ratio == Approx(std::pow(10.0, -6.0 / 20.0)).epsilon(0.01));
    // --set: a parameter after the sound is chosen, in its own units.
    const auto set = renderHeldA3("set", "--set gain=-6 --quiet");
    CHECK(peakOf(set.wav) / peakOf(plain.wav) == Approx(std::pow(10.0, -6.0 / 20.0)).epsilon(0.01));

    // A controller and no note: the Tanpura drone preset plays, the defaults stay silent.
    const auto cc = writeMidi(dir / "cc.mid", {track({{0, juce::MidiMessage::controllerEvent(1, 7, 100)}})}, 0);
    const auto drone = dir / "drone.wav";
    REQUIRE(render("--midi " + cc + " --preset 'tanpura DRONE' --duration 2 --quiet -o " + drone.string()).status == 0);
    CHECK(peakOf(readWav(drone)) > 0.05);
    REQUIRE(render("--midi " + cc + " --duration 2 --quiet -o " + drone.string()).status == 0);
    CHECK(peakOf(readWav(drone)) == 0.0);

    // The drone alone: no --midi at all, or a file without channel events, play the same drone.
    const auto alone = dir / "alone.wav", empty = dir / "empty.wav";
    const auto tempoOnly = writeMidi(dir / "tempo.mid", {track({{0, juce::MidiMessage::tempoMetaEvent(500000)}})}, 0);
    const auto o = render("--preset 'Tanpura drone' --duration 2 -o " + alone.string());
    INFO(o.output);
    REQUIRE(o.status == 0);
    CHECK_THAT(o.output, Catch::Matchers::Contains("the drone alone, no MIDI events"));
    REQUIRE(render("--midi " + tempoOnly + " --preset 'Tanpura drone' --duration 2 --quiet -o " + empty.string()).status == 0);
    const auto a = readWav(alone), b = readWav(empty);
    REQUIRE(a.left.size() == size_t(2 * 48000));
    CHECK(peakOf(a) > 0.05);
    CHECK(a.left == b.left);
    CHECK(a.right == b.right);
}

TEST_CASE("jawari-render --midi --second-core writes the same file to the last bit")
{
    // Eight notes on the Sitar's bridge, and the drone of the Tanpura drone preset with them.
    const auto dir = scratch();
    juce::MidiMessageSequence notes;
    for (int n = 0; n < 8; ++n)
    {
        notes.addEvent(juce::MidiMessage::noteOn(1, 48 + 3 * n, juce::uint8(70 + 5 * n)), 60.0 * n);
        notes.addEvent(juce::MidiMessage::noteOff(1, 48 + 3 * n), 900.0 + 60.0 * n);
    }
    const auto midi = writeMidi(dir / "chord.mid", {notes}, 0);
    for (const std::string preset : {"Sitar", "'Tanpura drone'"})
    {
        const auto one = dir / "one.wav", two = dir / "two.wav";
        const auto a = render("--midi " + midi + " --preset " + preset + " --duration 1.5 -o " + one.string());
        const auto b =
            render("--midi " + midi + " --preset " + preset + " --duration 1.5 --second-core -o " + two.string());
        INFO(preset << "\n" << a.output << "\n" << b.output);
        REQUIRE(a.status == 0);
        REQUIRE(b.status == 0);
        std::ifstream inOne(one, std::ios::binary), inTwo(two, std::ios::binary);
        const std::string bytesOne{std::istreambuf_iterator<char>(inOne), {}};
        const std::string bytesTwo{std::istreambuf_iterator<char>(inTwo), {}};
        CHECK(bytesOne.size() > size_t(3 * 2 * 48000));
        CHECK(bytesOne == bytesTwo);
        CHECK(peakOf(readWav(two)) > 0.05);
    }
}

namespace
{
std::string fileBytes(const fs::path& path)
{
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

// Bad MIDI files beside a good one's `bytes`: random bytes, the good file as type 2, a file holding an
// escape event (raw bytes for the device, not read by JUCE), and one holding only a tempo.
struct BadMidi
{
    std::string noise, typeTwo, escaped, tempoOnly;
};
BadMidi badMidiFiles(const fs::path& dir, const std::string& bytes)
{
    BadMidi bad;
    std::mt19937 rng(11);
    bad.noise.assign(2000, '\0');
    for (auto& c : bad.noise)
        c = char(rng());
    bad.typeTwo = bytes;
    bad.typeTwo[9] = 2;
    const juce::uint8 escape[] = {0xf7, 0x03, 0x90, 0x3c, 0x64};
    bad.escaped = writeMidi(dir / "escape.mid", {track({{0, juce::MidiMessage(escape, 5)}})}, 0);
    bad.tempoOnly = writeMidi(dir / "tempo-only.mid", {track({{0, juce::MidiMessage::tempoMetaEvent(500000)}})}, 0);
    return bad;
}
}  // namespace

TEST_CASE("jawari-render --midi refuses bad MIDI files, presets, states and option mixes with status 2")
{
    const auto dir = scratch();
    const auto wav = dir / "never.wav";
    const auto good = heldA3(dir / "good.mid");
    const std::string bytes = fileBytes(good);
    const auto [noise, typeTwo, escaped, tempoOnly] = badMidiFiles(dir, bytes);
    jawari::plugin::JawariAudioProcessor p;
    const auto xml = p.state().toXmlString().toStdString();

    struct Case
    {
        std::string arguments, expected;
    };
    const std::vector<Case> cases = {
        {"--midi " + (dir / "missing.mid").string(), "missing.mid: no such file"},
        {"--midi " + write(dir / "noise.mid", noise), "not a Standard MIDI File"},
        {"--midi " + write(dir / "cut.mid", bytes.substr(0, bytes.size() - 3)), "truncated: track 1 of 1 declares"},
        {"--midi " + write(dir / "type2.mid", typeTwo), "type 2 (independent sequences) is not supported"},
        {"--midi " + tempoOnly, "the MIDI file holds no notes, controllers or other channel events, and the "
                                "plugin's defaults has the drone off"},
        {"--midi " + tempoOnly + " --preset 'Tanpura drone'", "give its length with --duration S"},
        {"--preset 'Tanpura drone'", "no --midi file is given: the drone alone plays for ever"},
        {"--preset Sitar --duration 1", "preset 'Sitar (parabolic bridge)' has the drone off"},
        {"--midi " + escaped, "track 1: an escape event (F7)"},
        {"--midi " + good + " --preset Banjo", "no factory preset 'Banjo' (the presets: 'Default (tanpura bridge"},
        {"--midi " + good + " --state " + (dir / "missing.xml").string(), "missing.xml: no such file"},
        {"--midi " + good + " --state " + write(dir / "bad.xml", xml.substr(0, xml.size() / 2)), "bad.xml: not XML"},
        {"--midi " + good + " --state " + write(dir / "other.xml", "<Other/>"), "root element is <Other>"},
        {"--midi " + good + " --state " + write(dir / "latin1.xml", "<JawariState a=\"\xe9\"/>"), "not valid UTF-8"},
        {"--midi " + good + " --preset Default --state " + write(dir / "ok.xml", xml), "--preset or --state, not both"},
        {"--midi " + good + " " + jawari::test::resource("Scenes/paper-centre.json"),
         "a scene file or --midi, not both"},
        {"--midi " + good + " --method realtime", "--method applies to scene files"},
        {"--midi " + good + " --output-rate 8000", "--output-rate: the plugin runs at 22050 to 192000 Hz"},
        {"--midi " + good + " --duration 0", "--duration"},
        {"--midi " + good + " --format wav", "--format: unknown format 'wav' (expected int24 or float)"},
        {jawari::test::resource("Scenes/paper-centre.json") + " --preset Default", "--preset applies to renders through the plugin"},
        {jawari::test::resource("Scenes/paper-centre.json") + " --second-core", "--second-core applies to renders through the plugin"},
        {jawari::test::resource("Scenes/paper-centre.json") + " --set gain=-6", "--set applies to renders through the plugin"},
        {"--midi " + good + " --set banjo=1", "--set banjo=1: give ID=VALUE with a parameter's id"},
        {"--midi " + good + " --set gain", "--set gain: give ID=VALUE"},
        {"--midi " + good + " --set gain=loud", "--set gain"},
        {"--midi " + good + " --set sympathetic=14", "--set sympathetic: must be between 0"},
    };
    for (const auto& c : cases)
    {
        const auto o = render(c.arguments + " -o " + wav.string());
        INFO(c.arguments << "\n" << o.output);
        CHECK(o.status == 2);
        CHECK_THAT(o.output, Catch::Matchers::Contains(c.expected));
        CHECK_FALSE(fs::exists(wav));
    }
}

TEST_CASE("jawari-render --midi refuses every truncation of a good file with status 2, an existing output kept")
{
    const auto dir = scratch();
    const auto wav = dir / "never.wav";
    const std::string bytes = fileBytes(heldA3(dir / "good.mid"));
    // Every truncation of a good file is refused, and an existing output stays as it was.
    write(wav, "previous contents");
    for (size_t length = 0; length < bytes.size(); ++length)
    {
        const auto o = render("--midi " + write(dir / "cut.mid", bytes.substr(0, length)) + " -o " + wav.string());
        INFO("the first " << length << " of " << bytes.size() << " bytes\n" << o.output);
        CHECK(o.status == 2);
        CHECK_THAT(o.output, Catch::Matchers::Contains(length < 4 ? "not a Standard MIDI File" : "truncated"));
    }
    std::ifstream kept(wav);
    std::string text;
    std::getline(kept, text);
    CHECK(text == "previous contents");
}
