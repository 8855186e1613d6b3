// The plugin never takes its host down nor stalls it: every parameter at its edges and beyond
// (as a host sets them, and through a loaded state), random states by the hundred, through the
// real builder thread; prepareToPlay returning before the pack is built.

#include "PluginProcessor.h"
#include "Presets.h"

#include <catch2/catch.hpp>

#include <juce_audio_processors/juce_audio_processors.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

using namespace jawari;
using namespace jawari::plugin;

namespace
{
// What a few blocks with a note gave.
struct Outcome
{
    bool finite = true;
    double peak = 0.0;
};

// prepareToPlay, the builds waited for, then `blocks` blocks of 256 with a note from the first.
Outcome prepareAndPlay(JawariAudioProcessor& p, double rate, int blocks)
{
    p.prepareToPlay(rate, 256);
    REQUIRE(p.waitForBuilds(60000));
    juce::AudioBuffer<float> buffer(2, 256);
    Outcome o;
    for (int b = 0; b < blocks; ++b)
    {
        juce::MidiBuffer midi;
        if (b == 0)
            midi.addEvent(juce::MidiMessage::noteOn(1, 57, juce::uint8(110)), 0);
        buffer.clear();
        p.processBlock(buffer, midi);
        for (int c = 0; c < 2; ++c)
            for (int i = 0; i < 256; ++i)
            {
                const float v = buffer.getSample(c, i);
                o.finite = o.finite && std::isfinite(v);
                o.peak = std::max(o.peak, double(std::abs(v)));
            }
    }
    return o;
}

// A state whose one parameter holds `text` (the rest their defaults, draft quality).
std::string stateWith(const char* id, const std::string& text)
{
    return std::string("<JawariState version=\"2\"><Parameters><Param id=\"quality\" value=\"0\"/><Param id=\"")
           + id + "\" value=\"" + text + "\"/></Parameters></JawariState>";
}

// The drone off and the quality draft (hundreds of builds), the obstacle touching the string.
void quickAndTouching(JawariAudioProcessor& p)
{
    for (const auto& [id, value] : {std::pair{ids::quality, 0.0f}, std::pair{ids::drone, 0.0f}})
        if (auto* param = p.parameters().getParameter(id))
            param->setValueNotifyingHost(param->convertTo0to1(value));
}
}  // namespace

TEST_CASE("Every parameter at its edges, one step inside and past them, and not a number: no exception, sound",
          "[plugin][robustness]")
{
    constexpr float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    JawariAudioProcessor p;
    quickAndTouching(p);
    long cases = 0, silent = 0, problems = 0;
    for (const char* id : kParameterIds)
    {
        auto* param = p.parameters().getParameter(id);
        REQUIRE(param != nullptr);
        const float step = 1.0f / float(std::max(param->getNumSteps(), 2) - 1);
        for (const float normalised : {0.0f, step, 1.0f - step, 1.0f, nan, inf, -inf, -1.0f, 2.0f})
        {
            if (std::string(id) == ids::quality && !(normalised < 0.5f))
                continue;  // the slow qualities have their own test
            // What a host does: the normalised value as it sends it (JUCE keeps a NaN as it is).
            param->setValue(normalised);
            INFO(id << " at normalised " << normalised << ": " << param->getCurrentValueAsText());
            Outcome o;
            REQUIRE_NOTHROW(o = prepareAndPlay(p, 48000.0, 8));
            CHECK(o.finite);
            silent += o.peak > 0.0 ? 0 : 1;
            problems += p.problem().isEmpty() ? 0 : 1;
            CHECK(p.problem().isEmpty());
            ++cases;
            param->setValueNotifyingHost(param->getDefaultValue());
            quickAndTouching(p);
        }
    }
    INFO(cases << " cases: " << silent << " silent, " << problems << " refused");
    CHECK(cases > 8 * int(kParameterCount));
    CHECK(p.renderFaults() == 0);
    // Silence is right only where a parameter silences (gain at its minimum, the drone strength at 0):
    // a handful, never most.
    CHECK(silent < 10);
}

TEST_CASE("A loaded state's values that are not numbers, or beyond any range, load as defaults and play",
          "[plugin][robustness]")
{
    JawariAudioProcessor p;
    long cases = 0;
    for (const char* id : kParameterIds)
        for (const std::string text : {"nan", "inf", "-inf", "1e999", "-1e999", "1e38", "-1e38", "", "x"})
        {
            if (std::string(id) == ids::quality)
                continue;
            const auto xml = stateWith(id, text);
            INFO(xml);
            REQUIRE(p.setStateFromXml(xml.data(), xml.size()).wasOk());
            const float value = p.parameters().getRawParameterValue(id)->load();
            CHECK(std::isfinite(value));
            Outcome o;
            REQUIRE_NOTHROW(o = prepareAndPlay(p, 48000.0, 4));
            CHECK(o.finite);
            CHECK(p.problem().isEmpty());
            ++cases;
        }
    CHECK(cases == (int(kParameterCount) - 1) * 9);
}

TEST_CASE("A hundred random states build and play through the builder thread", "[plugin][robustness]")
{
    std::mt19937 random(19);
    JawariAudioProcessor p;
    long played = 0, loud = 0;
    for (int i = 0; i < 100; ++i)
    {
        for (const char* id : kParameterIds)
        {
            auto* param = p.parameters().getParameter(id);
            // Each value at an edge a quarter of the time, anywhere in range otherwise.
            const float u = std::uniform_real_distribution<float>(-0.25f, 1.25f)(random);
            param->setValueNotifyingHost(std::clamp(u, 0.0f, 1.0f));
        }
        if (auto* quality = p.parameters().getParameter(ids::quality))
            quality->setValueNotifyingHost(0.0f);  // draft: a hundred builds in seconds
        if (auto* core = p.parameters().getParameter(ids::secondCore))
            core->setValueNotifyingHost(0.0f);
        INFO("state " << i << ": " << p.state().toXmlString());
        Outcome o;
        REQUIRE_NOTHROW(o = prepareAndPlay(p, i % 2 == 0 ? 48000.0 : 44100.0, 4));
        CHECK(o.finite);
        CHECK(p.problem().isEmpty());
        loud += o.peak > 1e-4 ? 1 : 0;
        ++played;
    }
    INFO(loud << " of " << played << " states sounded above -80 dBFS");
    CHECK(loud > played / 2);  // a random gain, drone strength or obstacle silences only some
    CHECK(p.renderFaults() == 0);
}

TEST_CASE("The pluginval seeds' thread: a 1 mm bridge with its thread at 20 mm plays", "[plugin][robustness]")
{
    JawariAudioProcessor p;
    for (const auto& [id, value] :
         {std::pair{ids::obstacleShape, 1.0f}, std::pair{ids::obstacleWidth, 1.0f}, std::pair{ids::thread, 1.0f},
          std::pair{ids::threadPosition, 20.0f}, std::pair{ids::drone, 0.0f}})
    {
        auto* param = p.parameters().getParameter(id);
        param->setValueNotifyingHost(param->convertTo0to1(value));
    }
    const auto o = prepareAndPlay(p, 48000.0, 40);
    CHECK(o.finite);
    CHECK(o.peak > 1e-3);
    CHECK(p.problem().isEmpty());
}

TEST_CASE("prepareToPlay returns before the slowest pack is built, and the instrument then plays it",
          "[plugin][robustness]")
{
    // Quality paper, two polarisations, 96 kHz: the slowest build there is. prepareToPlay only
    // hands it to the builder thread: right after it returns the pack is not yet built, and a block
    // rendered meanwhile is silence, not a stall.
    JawariAudioProcessor p;
    for (const auto& [id, value] : {std::pair{ids::quality, 3.0f}, std::pair{ids::polarisations, 1.0f},
                                    std::pair{ids::drone, 0.0f}})
    {
        auto* param = p.parameters().getParameter(id);
        param->setValueNotifyingHost(param->convertTo0to1(value));
    }
    const auto start = std::chrono::steady_clock::now();
    p.prepareToPlay(96000.0, 64);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const bool builtAlready = p.waitForBuilds(0);
    INFO("prepareToPlay took " << seconds * 1e3 << " ms");
    CHECK_FALSE(builtAlready);
    const auto o = prepareAndPlay(p, 96000.0, 200);
    CHECK(o.finite);
    CHECK(o.peak > 1e-3);
    CHECK(p.getLatencySamples() > 0);
}

TEST_CASE("The Body parameters automated to their extremes at audio rate never trip the runaway guard",
          "[plugin][robustness][body]")
{
    // The Body mix, tuning and damping jump between their ends every 32-sample block (1.5 kHz), the
    // body itself changes every 250 blocks (none, tanpura, sitar: new packs from the builder thread),
    // and a fortissimo note starts every 25 blocks, through the Sitar (13 sympathetic strings) and the
    // Tanpura drone.
    for (const char* preset : {"Sitar", "Tanpura drone"})
    {
        JawariAudioProcessor p;
        p.setCurrentProgram(factoryPresetIndex(preset));
        p.parameters().getParameter(ids::quality)->setValueNotifyingHost(0.0f);
        p.prepareToPlay(48000.0, 32);
        REQUIRE(p.waitForBuilds(60000));
        const char* automated[] = {ids::bodyMix, ids::bodyTuning, ids::bodyDamping};
        juce::AudioBuffer<float> buffer(2, 32);
        bool finite = true;
        double peak = 0.0;
        for (int b = 0; b < 8 * 48000 / 32; ++b)
        {
            for (size_t i = 0; i < std::size(automated); ++i)
                p.parameters().getParameter(automated[i])->setValueNotifyingHost(float((b + int(i)) % 2));
            if (b % 250 == 0)
                p.parameters().getParameter(ids::body)->setValueNotifyingHost(float((b / 250) % 3) / 2.0f);
            juce::MidiBuffer midi;
            if (b % 25 == 0)
                midi.addEvent(juce::MidiMessage::noteOn(1, 48 + (b / 25) % 24, juce::uint8(127)), 0);
            buffer.clear();
            p.processBlock(buffer, midi);
            for (int c = 0; c < 2; ++c)
                for (int i = 0; i < 32; ++i)
                {
                    finite = finite && std::isfinite(buffer.getSample(c, i));
                    peak = std::max(peak, double(std::abs(buffer.getSample(c, i))));
                }
        }
        INFO(preset << ": peak " << peak << ", packs installed " << p.packsInstalled() << ", runaways "
                    << p.instrument().blowUps());
        CHECK(finite);
        CHECK(p.instrument().blowUps() == 0);
        CHECK(p.packsInstalled() > 10);  // the body really changed under the notes
        CHECK(peak > 1e-3);
        CHECK(p.problem().isEmpty());
    }
}
