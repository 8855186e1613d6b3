// The plugin as a host drives it, without a window: parameters changed from another thread while
// audio runs, every block size and sample rate, no allocation in processBlock, the first note's
// gain, parameter extremes and the bend automated at audio rate, MPE.

#include "PluginTestSupport.h"
#include "AllocationCounter.h"
#include "StoredReference.h"
#include "PluginEditor.h"
#include "PluginProcessor.h"
#include "Presets.h"
#include "offline/Analysis.h"
#include "offline/OfflineRender.h"
#include "offline/Scene.h"
#include "physics/body/FactoryBodies.h"
#include "realtime/voice/Voice.h"

#include <catch2/catch.hpp>

#include <juce_audio_processors/juce_audio_processors.h>
#include <juce_events/juce_events.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <optional>
#include <random>
#include <string>
#include <thread>
#include <utility>
#include <vector>

using namespace jawari;
using namespace jawari::plugin;
using namespace jawari::plugin_tests;

namespace
{
// A value another thread sets `param` to, from `value` drawn in [0, 1], or none for one it leaves
// alone. Quality "paper" would make the test slow; the penalty method blows up by design (its guard
// mutes it: VoiceTests) and the quadratised one went past +12 dBFS on stiff frets of a high exponent;
// a gain above 0 dB may take loud notes past the output guard's +12 dBFS (the extremes test takes it
// to +12 dB), and so does an obstacle above the string's rest line, which launches a string plucked
// into it with the energy its contact holds. Every other value of everything goes.
std::optional<float> fuzzedValue(juce::AudioProcessorParameter* param, float value)
{
    auto* ranged = dynamic_cast<juce::RangedAudioParameter*>(param);
    if (ranged == nullptr)
        return value;
    const auto id = ranged->getParameterID();
    if (id == ids::quality)
        return std::nullopt;
    if (id == ids::gain || id == ids::obstacleHeight)
        return ranged->convertTo0to1(std::min(ranged->convertFrom0to1(value), 0.0f));
    if (id == ids::method)
    {
        const auto method = kContactMethods[size_t(std::lround(ranged->convertFrom0to1(value)))].method;
        if (method == ContactMethod::penalty || method == ContactMethod::quadratised)
            return std::nullopt;
    }
    return value;
}
}  // namespace

TEST_CASE("Parameters changed from another thread while audio runs", "[plugin]")
{
    JawariAudioProcessor p;
    setParameter(p, ids::quality, 0.0f);  // draft keeps the test short
    prepare(p, 48000.0, 256);
    std::atomic<bool> running{true};
    std::thread fuzzer([&] {
        std::mt19937 rng(11);
        const auto& params = p.getParameters();
        while (running)
        {
            auto* param = params[int(rng() % unsigned(params.size()))];
            if (const auto value = fuzzedValue(param, std::uniform_real_distribution<float>(0.0f, 1.0f)(rng)))
                param->setValueNotifyingHost(*value);
            std::this_thread::sleep_for(std::chrono::microseconds(300));
        }
    });
    juce::AudioBuffer<float> buffer(2, 256);
    double peak = 0.0;
    bool finite = true;
    // At least 1500 blocks, and on until the builder has installed four packs (a loaded machine, or
    // structures with two polarisations, build more slowly), for at most 20 s.
    const auto giveUp = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    for (int b = 0; b < 1500 || (p.packsInstalled() <= 3 && std::chrono::steady_clock::now() < giveUp); ++b)
    {
        juce::MidiBuffer midi;
        if (b % 20 == 0)
            midi.addEvent(juce::MidiMessage::noteOn(1, 40 + b % 37, juce::uint8(60 + b % 60)), b % 256);
        if (b % 20 == 10)
            midi.addEvent(juce::MidiMessage::noteOff(1, 40 + (b - 10) % 37), 3);
        if (b % 7 == 0)
            midi.addEvent(juce::MidiMessage::pitchWheel(1, (b * 977) % 16384), 100);
        buffer.clear();
        p.processBlock(buffer, midi);
        peak = std::max<double>(peak, buffer.getMagnitude(0, 256));
        for (int c = 0; c < 2; ++c)
            for (int i = 0; i < 256; ++i)
                finite = finite && std::isfinite(buffer.getSample(c, i));
    }
    running = false;
    fuzzer.join();
    INFO("peak " << peak << ", packs installed " << p.packsInstalled() << ", samples limited "
                 << p.instrument().limitedSamples() << ", blow-ups " << p.instrument().blowUps());
    // What reaches the host is finite and within the guard's +12 dBFS, and no string ran away.
    // Not promised: that the guard never acts. Random corners of the parameters (wide frets with a
    // high exponent under a strong drone, a pickup beside the pluck) go past +12 dBFS now and then
    // at 0 dB of gain; the guard limits them.
    CHECK(finite);
    CHECK(peak <= kOutputCeiling);
    CHECK(p.instrument().blowUps() == 0);
    CHECK(p.packsInstalled() > 3);  // the structure changed under the audio and was rebuilt
}

TEST_CASE("Every block size from 1 to 4096 and sample rates from 44.1 to 192 kHz", "[plugin]")
{
    for (const double rate : {44100.0, 48000.0, 88200.0, 96000.0, 176400.0, 192000.0})
        for (const int block : {1, 17, 64, 512, 4096})
        {
            JawariAudioProcessor p;
            p.setCurrentProgram(factoryPresetIndex("Tanpura drone"));
            setParameter(p, ids::drone, 0.0f);
            setParameter(p, ids::quality, 0.0f);
            prepare(p, rate, block);
            const auto y = renderNote(p, rate, block, block == 1 ? 0.1 : 0.6, 69);
            INFO("rate " << rate << " block " << block << ": peak " << peakOf(y) << ", samples limited "
                         << p.instrument().limitedSamples() << ", blow-ups " << p.instrument().blowUps());
            // Finite and below full scale, the output guard (ceiling 4) untouched: measured peaks 0.182
            // to 0.185.
            bool finite = true;
            for (double v : y)
                finite = finite && std::isfinite(v) && std::abs(v) <= 1.0;
            CHECK(finite);
            CHECK(p.instrument().limitedSamples() == 0);
            CHECK(p.instrument().blowUps() == 0);
            CHECK(peakOf(y) > 1e-3);
            if (block == 512)
            {
                // In tune at every rate: A4 = 440 Hz.
                const double f = peakFrequency(y, rate, 400.0, 480.0, size_t(0.1 * rate));
                INFO("f0 " << f);
                CHECK(std::abs(f / 440.0 - 1.0) < 2e-3);
            }
        }
}

// The plugin's second-core worker marked real-time by its task hook, in each task it claims.
struct WorkerCounts
{
    test::RealtimeCounts counts;
    std::atomic<long> tasks{0};

    static void inTask(void* self)
    {
        auto& mark = *static_cast<WorkerCounts*>(self);
        test::countOnThisThread(&mark.counts);
        ++mark.tasks;
    }
};

namespace
{
// Block b's MIDI and automation in the allocation test: twelve notes, the pedal, the wheel, the body's
// mix, the sympathetic strings' scale, damping and level, all notes off.
void midiAt(JawariAudioProcessor& p, juce::MidiBuffer& midi, int b)
{
    midi.clear();
    if (b < 12)
        midi.addEvent(juce::MidiMessage::noteOn(1, 48 + b, juce::uint8(100)), b * 13);
    if (b == 30)
        midi.addEvent(juce::MidiMessage::controllerEvent(1, 64, 127), 0);
    if (b == 40)
        midi.addEvent(juce::MidiMessage::pitchWheel(1, 12000), 5);
    if (b == 60)
        for (int n = 0; n < 12; ++n)
            midi.addEvent(juce::MidiMessage::noteOff(1, 48 + n), n);
    if (b == 80)
        midi.addEvent(juce::MidiMessage::controllerEvent(1, 64, 0), 0);
    if (b == 90)
        p.parameters().getParameter(ids::bodyMix)->setValueNotifyingHost(0.3f);
    if (b == 95)  // the sympathetic strings retuned, damped, turned down
        for (const char* id : {ids::sympatheticScale, ids::sympatheticDamping, ids::sympatheticLevel})
            p.parameters().getParameter(id)->setValueNotifyingHost(0.7f);
    if (b == 100)
        midi.addEvent(juce::MidiMessage::allNotesOff(1), 0);
}

// A key pressed on the editor's keyboard between blocks (the message thread's work, not counted).
void pressKey(JawariAudioProcessor& p, int note, bool down)
{
    test::countAllocationsOnThisThread(false);
    if (down)
        p.keyboardState().noteOn(1, note, 0.8f);
    else
        p.keyboardState().noteOff(1, note, 0.0f);
    test::countAllocationsOnThisThread(true);
}

// Through a body, block b's new packs, each built off this thread (not counted): at 120 fewer
// sympathetic strings on their jawari, at 140 another body, at 160 none, the motion carried across
// (and a note there).
void bodyPackAt(JawariAudioProcessor& p, juce::MidiBuffer& midi, int b)
{
    if (b != 120 && b != 140 && b != 160)
        return;
    test::countAllocationsOnThisThread(false);
    if (b == 120)
    {
        setParameter(p, ids::sympathetic, 5.0f);
        setParameter(p, ids::sympatheticJawari, 1.0f);
    }
    else
    {
        setParameter(p, ids::body, b == 140 ? 2.0f : 0.0f);
        midi.addEvent(juce::MidiMessage::noteOn(1, 50, juce::uint8(100)), 0);
    }
    REQUIRE(p.waitForBuilds());
    test::countAllocationsOnThisThread(true);
}
}  // namespace

TEST_CASE("processBlock never allocates: notes, the editor's keyboard, bends, automation and a new pack, on one core "
          "or two, on rigid supports or through the body with sympathetic strings retuned and switched, the body "
          "changed under them",
          "[plugin]")
{
    for (const bool secondCore : {false, true})
    for (const bool body : {false, true})
    {
        INFO("second core " << secondCore << ", body " << body);
        WorkerCounts worker;  // before the processor: it outlives the worker's thread
        JawariAudioProcessor p;
        setParameter(p, ids::quality, 0.0f);
        setParameter(p, ids::secondCore, secondCore ? 1.0f : 0.0f);
        setParameter(p, ids::body, body ? 1.0f : 0.0f);
        setParameter(p, ids::pluckStyle, body ? 1.0f : 0.0f);  // the soft pluck's push from rest
        setParameter(p, ids::sympathetic, body ? 13.0f : 0.0f);
        // The worker in step with the audio thread: every string handed over is the worker's, and its
        // thread counts its allocations, whatever the machine's load.
        p.workerForTesting().setTaskHookForTesting(&WorkerCounts::inTask, &worker);
        p.workerForTesting().setPaceForTesting(StringWorker::Pace::inStep);
        prepare(p, 48000.0, 512);
        juce::AudioBuffer<float> buffer(2, 512);
        juce::MidiBuffer midi;
        midi.ensureSize(4096);
        // A structural change: the builder builds a new pack off this thread; processBlock takes it.
        setParameter(p, ids::obstaclePosition, 0.3f);
        REQUIRE(p.waitForBuilds());
        const long before = p.packsInstalled();
        long counted = 0, tasksBefore160 = 0;
        {
            test::CountAllocations guard;
            for (int b = 0; b < 200; ++b)
            {
                if (b % 10 == 5)
                    pressKey(p, 60 + (b / 20) % 12, b % 20 == 5);
                midiAt(p, midi, b);
                if (b == 160)
                    tasksBefore160 = worker.tasks.load();
                if (body)
                    bodyPackAt(p, midi, b);
                p.processBlock(buffer, midi);
            }
            counted = test::allocations;
        }
        INFO("packs installed during the run " << p.packsInstalled() - before << ", tasks the worker took "
                                                << worker.tasks.load() << ", its allocations "
                                                << worker.counts.allocations.load());
        CHECK(counted == 0);
        CHECK(worker.counts.allocations.load() == 0);
        // A body's strings step in lockstep, on this thread; taken off it at 160, they go to the worker.
        CHECK((tasksBefore160 > 0) == (secondCore && !body));
        CHECK((worker.tasks.load() > 0) == secondCore);
        CHECK(p.packsInstalled() > before);
    }
}

TEST_CASE("processBlock never allocates with DAFx-16's damped thread across a grazing bridge", "[plugin]")
{
    // The thread's point never leaves the contact solve, which then takes the bilateral path or the
    // coupled Newton at every step: notes, a bend and the thread's stiffness moved (a new pack).
    JawariAudioProcessor p;
    setParameter(p, ids::quality, 0.0f);
    setParameter(p, ids::obstacleShape, 1.0f);  // the parabolic bridge
    setParameter(p, ids::obstacleWidth, 10.0f);
    setParameter(p, ids::bridgeCurvature, 0.2f);
    setParameter(p, ids::thread, 1.0f);
    REQUIRE(parameterValue(p, ids::threadModel) == 0.0f);  // damped
    prepare(p, 48000.0, 512);
    setParameter(p, ids::threadStiffness, 300.0f);
    REQUIRE(p.waitForBuilds());
    juce::AudioBuffer<float> buffer(2, 512);
    juce::MidiBuffer none;
    p.processBlock(buffer, none);  // takes the built pack
    const auto& built = p.instrument().pack()->structure;
    REQUIRE(built.thread);
    REQUIRE(built.threadModel == ThreadModel::springDamper);
    REQUIRE(built.threadStiffness == Approx(3e5));
    juce::MidiBuffer midi;
    midi.ensureSize(4096);
    long counted = 0;
    {
        test::CountAllocations guard;
        for (int b = 0; b < 100; ++b)
        {
            midi.clear();
            if (b < 6)
                midi.addEvent(juce::MidiMessage::noteOn(1, 50 + b, juce::uint8(100)), b * 17);
            if (b == 40)
                midi.addEvent(juce::MidiMessage::pitchWheel(1, 12000), 5);
            p.processBlock(buffer, midi);
        }
        counted = test::allocations;
    }
    CHECK(counted == 0);
    CHECK(p.instrument().blowUps() == 0);
    CHECK(p.instrument().limitedSamples() == 0);
}


TEST_CASE("After prepareToPlay a first note plays at the parameters' gain, not gliding from the default", "[plugin]")
{
    // The gain and the obstacle glide over 20 ms when automated; where playback starts they begin
    // at their values, so a note on the first sample with the gain at -6 dB is 6 dB down throughout.
    JawariAudioProcessor unity, quieter;
    setParameter(quieter, ids::gain, -6.0f);
    prepare(unity, 48000.0, 512);
    prepare(quieter, 48000.0, 512);
    const auto a = renderNote(unity, 48000.0, 512, 0.02, 57);
    const auto b = renderNote(quieter, 48000.0, 512, 0.02, 57);
    CHECK(peakOf(b) / peakOf(a) == Approx(std::pow(10.0, -6.0 / 20.0)).epsilon(1e-4));
}

namespace
{
// Block b of a hammering: a fortissimo note every 50 blocks, released 25 later, the pitch wheel
// between its ends at every block.
void hammerBlock(JawariAudioProcessor& p, juce::AudioBuffer<float>& buffer, int b)
{
    juce::MidiBuffer midi;
    if (b % 50 == 0)
        midi.addEvent(juce::MidiMessage::noteOn(1, 30 + (b / 50) % 60, juce::uint8(127)), 0);
    if (b % 50 == 25)
        midi.addEvent(juce::MidiMessage::noteOff(1, 30 + (b / 50) % 60), 0);
    midi.addEvent(juce::MidiMessage::pitchWheel(1, (b % 2) * 16383), 0);
    buffer.clear();
    p.processBlock(buffer, midi);
}
}  // namespace

TEST_CASE("Parameter extremes automated at audio rate for twenty seconds stay finite and bounded", "[plugin]")
{
    JawariAudioProcessor p;
    setParameter(p, ids::quality, 0.0f);
    setParameter(p, ids::drone, 1.0f);
    setParameter(p, ids::droneTempo, 200.0f);
    prepare(p, 48000.0, 32);
    // Every continuous parameter jumps between its ends every 32-sample block (1.5 kHz), notes
    // hammer away; the structural ones change too (the bridge moves every 1000 blocks, 0.67 s),
    // so the builder keeps swapping packs.
    const char* rt[] = {ids::obstacleHeight, ids::obstacleStiffness, ids::obstacleExponent,  ids::decayScale,
                        ids::airDamping,     ids::viscoelasticLoss,  ids::thermoelasticLoss, ids::gain,
                        ids::bendRange,      ids::humanise,          ids::droneStrength,     ids::droneTonic};
    juce::AudioBuffer<float> buffer(2, 32);
    double peak = 0.0;
    bool finite = true;
    const int blocks = 20 * 48000 / 32;
    for (int b = 0; b < blocks; ++b)
    {
        for (size_t i = 0; i < std::size(rt); ++i)
            p.parameters().getParameter(rt[i])->setValueNotifyingHost(((b + int(i)) % 2) == 0 ? 0.0f : 1.0f);
        if (b % 1000 == 0)
            p.parameters().getParameter(ids::obstaclePosition)->setValueNotifyingHost(float(b % 3000) / 3000.0f);
        hammerBlock(p, buffer, b);
        finite = finite && allFinite(buffer);
        peak = std::max<double>(peak, buffer.getMagnitude(0, 32));
    }
    INFO("peak " << peak << ", packs installed " << p.packsInstalled() << ", recoveries " << p.instrument().blowUps()
                 << ", output samples guarded " << p.instrument().limitedSamples() << ", most Newton iterations "
                 << p.instrument().maxIterations());
    // The output guard acts here (the next test says why), so the output's finiteness and its peak
    // at the ceiling are the guard's doing; what the strings do is asserted: none ran away.
    CHECK(finite);
    CHECK(p.instrument().blowUps() == 0);
    CHECK(peak > 1e-3);
}

// A sounding string is retuned at every chunk while its damping moves, the bend's one-pole rippling
// at the chunk rate (the wheel toggled every 32 samples): each retune keeps every mode's action
// (E / omega, ModalSolver::keepModeActions), so the pitch moving back and forth pumps nothing.
// Keeping the modes' displacements instead, the output guard held the strings at +12 dBFS for 95 %
// of the samples over 5 s.
TEST_CASE("The bend and the damping automated at audio rate pump no energy into the strings", "[plugin]")
{
    JawariAudioProcessor p;
    setParameter(p, ids::quality, 0.0f);
    setParameter(p, ids::bendRange, 24.0f);
    prepare(p, 48000.0, 32);
    juce::AudioBuffer<float> buffer(2, 32);
    for (int b = 0; b < 5 * 48000 / 32; ++b)
    {
        p.parameters().getParameter(ids::decayScale)->setValueNotifyingHost(float(b % 2));
        hammerBlock(p, buffer, b);
    }
    INFO("output samples guarded " << p.instrument().limitedSamples());
    CHECK(p.instrument().limitedSamples() == 0);
}


TEST_CASE("MPE through processBlock: a note bends on its own channel while another holds its pitch", "[plugin]")
{
    JawariAudioProcessor p;
    prepare(p, 48000.0, 256);
    setParameter(p, ids::obstacleHeight, -5.0f);  // free strings: clean pitches
    setParameter(p, ids::mpe, 1.0f);
    REQUIRE(p.waitForBuilds());
    juce::AudioBuffer<float> buffer(2, 256);
    std::vector<double> out;
    for (int block = 0; block < 300; ++block)  // 1.6 s
    {
        juce::MidiBuffer midi;
        if (block == 0)
        {
            midi.addEvent(juce::MidiMessage::noteOn(2, 57, juce::uint8(100)), 0);  // A3 on channel 2
            midi.addEvent(juce::MidiMessage::noteOn(3, 52, juce::uint8(100)), 0);  // E3 on channel 3
        }
        if (block == 20)  // channel 2 bent by 2 of its 48 semitones: A3 to B3
            midi.addEvent(juce::MidiMessage::pitchWheel(2, 8192 + 8192 * 2 / 48), 0);
        buffer.clear();
        p.processBlock(buffer, midi);
        for (int i = 0; i < 256; ++i)
            out.push_back(buffer.getSample(0, i) + buffer.getSample(1, i));
    }
    const double b3 = 440.0 * std::pow(2.0, -10.0 / 12.0), e3 = 440.0 * std::pow(2.0, -17.0 / 12.0);
    const double bent = peakFrequency(out, 48000.0, 235.0, 255.0, 12000, out.size() - 12000);
    const double held = peakFrequency(out, 48000.0, 158.0, 170.0, 12000, out.size() - 12000);
    INFO("bent note " << bent << " Hz (B3 " << b3 << "), held " << held << " Hz (E3 " << e3 << ")");
    CHECK(std::abs(bent / b3 - 1.0) < 0.003);
    CHECK(std::abs(held / e3 - 1.0) < 0.003);
    CHECK(p.instrument().slotChannel(0) == 2);
}
