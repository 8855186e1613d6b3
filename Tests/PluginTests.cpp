// The plugin without a host or a window: the real AudioProcessor rendered offline and compared
// with the reference solver; what pluginval checks (state round trip, parameters changed from
// another thread while audio runs, block sizes and sample rates, no allocation in processBlock);
// and the robustness checks of setStateInformation and parameter extremes.

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
#include <random>
#include <string>
#include <thread>
#include <utility>
#include <vector>

using namespace jawari;
using namespace jawari::plugin;

namespace
{
void setParameter(JawariAudioProcessor& p, const char* id, float value)
{
    auto* param = p.parameters().getParameter(id);
    REQUIRE(param != nullptr);
    param->setValueNotifyingHost(param->convertTo0to1(value));
}

// prepareToPlay, and the builder thread's pack for the parameters waited for: the next block plays it.
void prepare(JawariAudioProcessor& p, double rate, int block)
{
    p.prepareToPlay(rate, block);
    REQUIRE(p.waitForBuilds());
}

float parameterValue(JawariAudioProcessor& p, const char* id)
{
    return p.parameters().getRawParameterValue(id)->load();
}

// Renders `seconds` with `first` in the first block (an empty buffer after); returns the left channel.
std::vector<double> render(JawariAudioProcessor& p, double rate, int block, double seconds,
                           const juce::MidiBuffer& first = {})
{
    juce::AudioBuffer<float> buffer(2, block);
    std::vector<double> out;
    const long total = std::lround(seconds * rate);
    for (long n = 0; n < total; n += block)
    {
        juce::MidiBuffer midi;
        if (n == 0)
            midi = first;
        buffer.clear();
        p.processBlock(buffer, midi);
        for (int i = 0; i < block && n + i < total; ++i)
            out.push_back(buffer.getSample(0, i));
    }
    return out;
}

// Renders `seconds` with one note held from the start; returns the left channel.
std::vector<double> renderNote(JawariAudioProcessor& p, double rate, int block, double seconds, int note = 55,
                               juce::uint8 velocity = 100)
{
    juce::MidiBuffer midi;
    midi.addEvent(juce::MidiMessage::noteOn(1, note, velocity), 0);
    return render(p, rate, block, seconds, midi);
}

double peakOf(const std::vector<double>& y)
{
    double m = 0.0;
    for (double v : y)
        m = std::max(m, std::abs(v));
    return m;
}

// Finite and within the output guard's ceiling (+12 dBFS: extreme gains and obstacles may pass full
// scale, as a float pipeline carries them).
bool allFinite(const juce::AudioBuffer<float>& b)
{
    for (int c = 0; c < b.getNumChannels(); ++c)
        for (int i = 0; i < b.getNumSamples(); ++i)
            if (!std::isfinite(b.getSample(c, i)) || std::abs(b.getSample(c, i)) > kOutputCeiling)
                return false;
    return true;
}
}  // namespace

namespace
{
// What a note of the plugin must match in the reference's output: its fundamental's range (Hz), and
// the log-spectral distance's bound (dB).
struct ReferenceBound
{
    double lowHz, highHz, lsd;
};

// The plugin on `preset` (drone off, standard, the string in the centre, plucked from rest as a
// scene is: the sharp pluck), through its body or on rigid supports, plays `note` at velocity 100
// (1.5 mm) for 1.2 s; against `reference` scaled as the plugin scales its pickup: the same pitch,
// within the bound, the same peak from 5 ms on, and no blow-up.
void checkAgainstReference(const char* preset, bool body, const std::vector<double>& reference, int note,
                           const ReferenceBound& bound)
{
    JawariAudioProcessor p;
    p.setCurrentProgram(factoryPresetIndex(preset));
    setParameter(p, ids::drone, 0.0f);
    setParameter(p, ids::quality, 1.0f);      // standard
    setParameter(p, ids::stereoWidth, 0.0f);  // the string in the centre, as the scale below assumes
    setParameter(p, ids::pluckStyle, 0.0f);        // the scene's pluck: its shape, released
    if (!body)
        setParameter(p, ids::body, 0.0f);
    const double rate = 48000.0;
    prepare(p, rate, 512);
    const auto y = renderNote(p, rate, 512, 1.2, note, 100);
    const int latency = p.getLatencySamples();
    // The plugin's output is the centre-panned pickup x outputScale, delayed by its latency.
    const double scale = p.instrument().pack()->outputScale * std::sqrt(0.5);
    std::vector<double> a(y.begin() + latency, y.end());
    std::vector<double> b(reference.begin(), reference.end());
    const size_t n = std::min(a.size(), b.size());
    a.resize(n);
    b.resize(n);
    for (double& v : b)
        v *= scale;
    const double lsd = logSpectralDistance(a, b, rate, 1.0);
    const double l2 = relativeL2(a, b, 4800);
    const double fa = peakFrequency(a, rate, bound.lowHz, bound.highHz, 0, 48000);
    const double fb = peakFrequency(b, rate, bound.lowHz, bound.highHz, 0, 48000);
    const auto* pack = p.instrument().pack();
    // The peak from 5 ms on: a note from rest starts with the string held in its shape, a step the
    // plugin's decimator (history at rest, several strings mixed) rings on by up to 8 % (the bass,
    // read at 0.1 L beside its pluck at 0.12 L), while the reference's resampler has always seen it.
    const std::vector<double> aLater(a.begin() + 240, a.end()), bLater(b.begin() + 240, b.end());
    INFO(preset << (body ? " through its body" : "") << ": plugin " << pack->modes << " modes x"
                << pack->voices[0]->oversampling() << "; f0 " << fa << " vs " << fb << " Hz; LSD(0-1 s) " << lsd
                << " dB; relL2(0-100 ms) " << l2 << "; peak " << peakOf(a) << " vs " << peakOf(b) << "; from 5 ms "
                << peakOf(aLater) << " vs " << peakOf(bLater));
    CHECK(std::abs(fa / fb - 1.0) < 1e-3);
    CHECK(lsd < bound.lsd);
    CHECK(peakOf(aLater) == Approx(peakOf(bLater)).epsilon(0.05));
    CHECK(p.instrument().blowUps() == 0);
}
}  // namespace

TEST_CASE("Headless render of the factory presets matches the reference solver", "[plugin]")
{
    // The real AudioProcessor, no window: the preset of a paper scene, the note of the scene's
    // string (G3, 196 Hz), velocity 100 (the scene's 1.5 mm pluck at its point), 1.2 s rendered;
    // the reference solver renders the scene file itself (1001 modes at 2 MHz), or the bridge scenes
    // their converged configurations, stored (docs/measurements.md, "The reference's convergence on
    // bridges"): the Sitar's 4001 modes at 4 MHz with points L/16032 apart, the thread's 2003 modes
    // at 16 MHz with the rate extrapolated.
    // The Sitar and the bass take their own strings' notes (A3, E1), and the bass's scene is rendered
    // with the plugin's pluck at velocity 100 (1.5 mm). The thread's scene plays two polarisations, its
    // tension 180.3256 N so that the coupled mode most like the vertical's first sounds G3, as the
    // plugin tunes it (the spring alone would raise it by 5e-4).
    struct Case
    {
        const char* preset;
        const char* scene;
        double lowHz, highHz;  // where the fundamental is (the centre obstacle raises it by 4/3)
        double lsdBound;       // the standard quality's documented bounds (README): 2 and 3 dB
        int note = 55;
        bool stored = false;   // the scene's converged reference, stored (StoredReference.h)
    };
    for (const auto& c :
         {Case{"Paper centre obstacle", "paper-centre.json", 230.0, 290.0, 2.0},
          Case{"Tanpura drone", "paper-tanpura.json", 180.0, 210.0, 3.0},
          // Its rigid thread takes the static-exact forcing (VoicePack.cpp): 2.95 dB at the
          // bridge table's standard (3x), 3.54 with the paper's gain.
          Case{"Tanpura thread (jiva, two polarisations)", "tanpura-thread.json", 180.0, 210.0, 3.0, 55, true},
          Case{"Sitar (parabolic bridge)", "sitar-bridge.json", 200.0, 260.0, 3.0, 57, true},
          Case{"Bass fret buzz", "bass-frets.json", 35.0, 50.0, 3.0, 28}})
    {
        Scene scene = loadSceneFile(std::string(JAWARI_RESOURCES_DIR) + "/Scenes/" + c.scene);
        if (c.stored)  // rendered from the scene as it stands: its pluck must be the plugin's
            REQUIRE(scene.excitation.amplitude == 1.5e-3);
        scene.excitation.amplitude = 1.5e-3;
        const auto reference = c.stored ? test::storedReference(std::filesystem::path(c.scene).stem().string()).samples
                                        : renderScene(scene).output;
        checkAgainstReference(c.preset, false, reference, c.note, {c.lowHz, c.highHz, c.lsdBound});
    }
}

TEST_CASE("Headless render through the tanpura body matches the reference solver through it", "[plugin][body]")
{
    // The Tanpura drone preset's string and bridge on its body, its radiated sound (the body's mix at
    // 100 %), plucked as the scene is; the reference steps the same body under the scene's bridge and
    // reads the same pressure. The bound is the standard quality's on this scene without the body
    // (3 dB, README): measured 2.27 dB through it.
    Scene scene = loadSceneFile(std::string(JAWARI_RESOURCES_DIR) + "/Scenes/paper-tanpura.json");
    scene.excitation.amplitude = 1.5e-3;
    scene.body = SceneBody{*factoryBody("tanpura"), {0}, 1.0, {}};
    scene.pickup.quantity = PickupQuantity::pressure;
    checkAgainstReference("Tanpura drone", true, renderScene(scene).output, 55, {180.0, 210.0, 3.0});
}

TEST_CASE("The state round-trips every parameter and the damping curve", "[plugin]")
{
    JawariAudioProcessor a;
    std::mt19937 rng(7);
    for (auto* param : a.getParameters())
        param->setValueNotifyingHost(std::uniform_real_distribution<float>(0.0f, 1.0f)(rng));
    for (int i = 0; i < kDampingCurvePoints; ++i)
        a.setDampingCurvePoint(i, 0.25f + 0.5f * float(i));
    juce::MemoryBlock blob;
    a.getStateInformation(blob);
    JawariAudioProcessor b;
    b.setStateInformation(blob.getData(), int(blob.getSize()));
    int checked = 0;
    for (int i = 0; i < a.getParameters().size(); ++i)
    {
        auto* pa = dynamic_cast<juce::RangedAudioParameter*>(a.getParameters()[i]);
        auto* pb = dynamic_cast<juce::RangedAudioParameter*>(b.getParameters()[i]);
        INFO(pa->getParameterID());
        CHECK(pa->convertFrom0to1(pa->getValue()) == Approx(pb->convertFrom0to1(pb->getValue())).margin(1e-5));
        ++checked;
    }
    CHECK(checked == int(kParameterCount));
    for (int i = 0; i < kDampingCurvePoints; ++i)
        CHECK(b.dampingCurvePoint(i) == Approx(std::clamp(0.25f + 0.5f * float(i), 0.125f, 8.0f)));
}

TEST_CASE("The factory presets keep their program numbers: a new one comes last", "[plugin]")
{
    // A host recalls a program by its number; a preset inserted before another would change the sound
    // of every session saved on the later one.
    const char* names[] = {"Default (tanpura bridge, no drone)", "Paper centre obstacle", "Tanpura drone",
                           "Sitar (parabolic bridge)", "Bass fret buzz", "Tanpura thread (jiva, two polarisations)",
                           "Sitar Sa-Pa (sympathetic strings for a drone)"};
    JawariAudioProcessor p;
    REQUIRE(p.getNumPrograms() == int(std::size(names)));
    for (int i = 0; i < p.getNumPrograms(); ++i)
        CHECK(p.getProgramName(i) == juce::String(names[i]));
}

TEST_CASE("The factory presets play through their instrument's body: tanpuras the tanpura's, sitars the sitar's",
          "[plugin]")
{
    // The Body choice: 0 none, 1 tanpura, 2 sitar (kBodyNames).
    JawariAudioProcessor p;
    int tanpuras = 0, sitars = 0;
    for (int i = 0; i < p.getNumPrograms(); ++i)
    {
        p.setCurrentProgram(i);
        const auto name = p.getProgramName(i);
        INFO(name << ": body " << parameterValue(p, ids::body));
        if (name.startsWith("Tanpura"))
        {
            CHECK(parameterValue(p, ids::body) == 1.0f);
            ++tanpuras;
        }
        if (name.startsWith("Sitar"))
        {
            CHECK(parameterValue(p, ids::body) == 2.0f);
            ++sitars;
        }
    }
    CHECK(tanpuras == 2);
    CHECK(sitars == 2);
}

TEST_CASE("A state or preset saved with the old id droneLevel restores the drone strength", "[plugin]")
{
    // The state of an older version: drone strength saved as "droneLevel".
    auto stateWithDroneLevel = [](double value) {
        juce::ValueTree tree("JawariState");
        tree.setProperty("version", 2, nullptr);
        juce::ValueTree params("Parameters");
        juce::ValueTree param("Param");
        param.setProperty("id", "droneLevel", nullptr);
        param.setProperty("value", value, nullptr);
        params.appendChild(param, nullptr);
        tree.appendChild(params, nullptr);
        return tree;
    };
    JawariAudioProcessor p;
    REQUIRE(parameterValue(p, ids::droneStrength) == Approx(0.7f));
    juce::MemoryBlock blob;
    juce::AudioProcessor::copyXmlToBinary(*stateWithDroneLevel(0.35).createXml(), blob);
    p.setStateInformation(blob.getData(), int(blob.getSize()));
    CHECK(parameterValue(p, ids::droneStrength) == Approx(0.35f));

    // A user preset file of that version.
    juce::TemporaryFile preset(".jawaripreset");
    REQUIRE(stateWithDroneLevel(0.9).createXml()->writeTo(preset.getFile()));
    REQUIRE(p.loadUserPreset(preset.getFile()).wasOk());
    CHECK(parameterValue(p, ids::droneStrength) == Approx(0.9f));

    // Both ids in one state: the current one wins.
    auto both = stateWithDroneLevel(0.2);
    juce::ValueTree current("Param");
    current.setProperty("id", ids::droneStrength, nullptr);
    current.setProperty("value", 0.6, nullptr);
    both.getChildWithName("Parameters").appendChild(current, nullptr);
    p.setState(both);
    CHECK(parameterValue(p, ids::droneStrength) == Approx(0.6f));
}

TEST_CASE("A thread saved before the thread had a model plays rigid as it did; a new one is DAFx-16's damped thread",
          "[plugin]")
{
    auto stateWithThread = [](int version) {
        juce::ValueTree tree("JawariState");
        tree.setProperty("version", version, nullptr);
        juce::ValueTree params("Parameters");
        juce::ValueTree param("Param");
        param.setProperty("id", ids::thread, nullptr);
        param.setProperty("value", 1.0, nullptr);
        params.appendChild(param, nullptr);
        tree.appendChild(params, nullptr);
        return tree;
    };
    JawariAudioProcessor p;
    CHECK(parameterValue(p, ids::threadModel) == 0.0f);  // damped
    p.setState(stateWithThread(2));
    CHECK(parameterValue(p, ids::thread) == 1.0f);
    CHECK(parameterValue(p, ids::threadModel) == 1.0f);  // rigid, as version 2 played it
    p.setState(stateWithThread(3));
    CHECK(parameterValue(p, ids::threadModel) == 0.0f);
    const auto structure = ParameterReader(p.parameters()).structure(48000.0);
    CHECK(structure.threadModel == ThreadModel::springDamper);
    CHECK(structure.threadStiffness == Approx(1.2e5));
    CHECK(structure.threadDamping == Approx(1.2));
}

TEST_CASE("The parameters: their order, the engine's choice names and unchanged defaults", "[plugin]")
{
    JawariAudioProcessor p;
    const auto& params = p.getParameters();
    REQUIRE(size_t(params.size()) == kParameterCount);
    for (size_t i = 0; i < kParameterCount; ++i)
    {
        auto* ranged = dynamic_cast<juce::RangedAudioParameter*>(params[int(i)]);
        REQUIRE(ranged != nullptr);
        CHECK(ranged->getParameterID() == kParameterIds[i]);
    }
    auto choicesOf = [&](const char* id) {
        auto* choice = dynamic_cast<juce::AudioParameterChoice*>(p.parameters().getParameter(id));
        REQUIRE(choice != nullptr);
        return choice->choices;
    };
    CHECK(choicesOf(ids::quality) == juce::StringArray{"draft", "standard", "high", "paper"});
    CHECK(choicesOf(ids::method)
          == juce::StringArray{"energy-conserving", "quadratised", "penalty", "quadratic spline"});
    CHECK(choicesOf(ids::body) == juce::StringArray{"none", "tanpura", "sitar"});
    CHECK(choicesOf(ids::pluckStyle) == juce::StringArray{"sharp", "soft"});

    // The defaults as the player sees them: the engine's InstrumentControls and InstrumentStructure
    // defaults, some in other units, and the plugin's own bridge and pickup positions.
    const std::pair<const char*, float> defaults[] = {{ids::stringType, 0.0f},
                                                      {ids::obstacleShape, 0.0f},
                                                      {ids::obstaclePosition, 0.006f},
                                                      {ids::obstacleHeight, 0.0f},
                                                      {ids::obstacleStiffness, 13.0f},
                                                      {ids::obstacleExponent, 1.3f},
                                                      {ids::obstacleWidth, 1.0f},
                                                      {ids::bridgeCurvature, 2.0f},
                                                      {ids::pluckPosition, 0.5f},
                                                      {ids::pickupPosition, 0.992f / 1.002f},
                                                      {ids::decayScale, 1.0f},
                                                      {ids::airDamping, 1.0f},
                                                      {ids::viscoelasticLoss, 0.006f},
                                                      {ids::thermoelasticLoss, 1.38f},
                                                      {ids::inharmonicity, 1.78e-5f},
                                                      {ids::release, 0.4f},
                                                      {ids::quality, 1.0f},
                                                      {ids::method, 3.0f},
                                                      {ids::gain, 0.0f},
                                                      {ids::bendRange, 2.0f},
                                                      {ids::drone, 0.0f},
                                                      {ids::droneTonic, 49.0f},
                                                      {ids::droneFirst, 0.0f},
                                                      {ids::droneTempo, 60.0f},
                                                      {ids::humanise, 0.2f},
                                                      {ids::droneStrength, 0.7f},
                                                      {ids::droneTuning, 0.0f},
                                                      {ids::droneSaHz, 0.0f},
                                                      {ids::droneFine1, 0.0f},
                                                      {ids::droneFine2, 0.0f},
                                                      {ids::droneFine3, 0.0f},
                                                      {ids::droneFine4, 0.0f},
                                                      {ids::mpe, 0.0f},
                                                      {ids::mpeBendRange, 48.0f},
                                                      {ids::stereoWidth, 0.6f},
                                                      {ids::secondCore, 0.0f},
                                                      {ids::polarisations, 0.0f},
                                                      {ids::thread, 0.0f},
                                                      {ids::threadPosition, 2.0f},
                                                      {ids::threadDiameter, 0.2f},
                                                      {ids::threadModel, 0.0f},
                                                      {ids::threadStiffness, 120.0f},
                                                      {ids::threadDamping, 1.2f},
                                                      {ids::pluckStyle, 0.0f},
                                                      {ids::body, 0.0f},
                                                      {ids::bodyMix, 1.0f},
                                                      {ids::bodyTuning, 1.0f},
                                                      {ids::bodyDamping, 1.0f},
                                                      {ids::sympathetic, 0.0f},
                                                      {ids::sympatheticScale, 3.0f},
                                                      {ids::sympatheticIntonation, 0.0f},
                                                      {ids::sympatheticDamping, 1.0f},
                                                      {ids::sympatheticLevel, 1.0f},
                                                      {ids::sympatheticJawari, 0.0f},
                                                      {ids::voices, 8.0f}};
    CHECK(std::size(defaults) == kParameterCount);
    for (const auto& [id, value] : defaults)
    {
        INFO(id);
        CHECK(parameterValue(p, id) == Approx(value).epsilon(1e-6).margin(1e-6));
    }
    auto defaultText = [&](const char* id) {
        auto* param = p.parameters().getParameter(id);
        return param->getText(param->getDefaultValue(), 100);
    };
    CHECK(defaultText(ids::obstacleStiffness) == "1.0e13 N/m^2.3");
    CHECK(defaultText(ids::viscoelasticLoss) == "0.0060");
    CHECK(defaultText(ids::thermoelasticLoss) == "1.38e-4");
    CHECK(defaultText(ids::obstacleWidth) == "1.00 mm");
}

TEST_CASE("Parameter values read in a player's units and typed text reads back", "[plugin]")
{
    JawariAudioProcessor p;
    auto textOf = [&](const char* id, float value) {
        auto* param = p.parameters().getParameter(id);
        return param->getText(param->convertTo0to1(value), 100);
    };
    auto valueOf = [&](const char* id, const juce::String& typed) {
        auto* param = p.parameters().getParameter(id);
        return param->convertFrom0to1(param->getValueForText(typed));
    };
    // Positions in mm from the bridge end of the string chosen: 1.002 m steel, 0.864 m bass E.
    CHECK(textOf(ids::obstaclePosition, 0.006f) == "6.0 mm");
    CHECK(textOf(ids::pluckPosition, 0.5f) == "501 mm");
    CHECK(textOf(ids::pickupPosition, 0.992f / 1.002f) == "992 mm");
    CHECK(valueOf(ids::obstaclePosition, "12 mm") == Approx(0.012 / 1.002));
    CHECK(valueOf(ids::pluckPosition, "25 %") == Approx(0.25));
    setParameter(p, ids::stringType, 2.0f);
    CHECK(textOf(ids::obstaclePosition, 0.006f) == "5.2 mm");
    setParameter(p, ids::stringType, 0.0f);
    // The stiffness as K in the unit its exponent gives it; K or log10 K typed.
    CHECK(textOf(ids::obstacleStiffness, 12.5f) == "3.2e12 N/m^2.3");
    setParameter(p, ids::obstacleExponent, 2.0f);
    CHECK(textOf(ids::obstacleStiffness, 13.0f) == "1.0e13 N/m^3");
    CHECK(valueOf(ids::obstacleStiffness, "1e11") == Approx(11.0f));
    CHECK(valueOf(ids::obstacleStiffness, "11.5") == Approx(11.5f));
    // No "-0.00" for a height that rounds to zero; heights, losses and notes in their units.
    CHECK(textOf(ids::obstacleHeight, -0.00001f) == "0.00 mm");
    CHECK(textOf(ids::obstacleHeight, -0.25f) == "-0.25 mm");
    CHECK(textOf(ids::inharmonicity, 1.78e-5f) == "1.78e-5");
    CHECK(valueOf(ids::thermoelasticLoss, "2.5e-4") == Approx(2.5f));
    CHECK(textOf(ids::droneTonic, 49.0f) == "C#3");
    CHECK(valueOf(ids::droneTonic, "C4") == Approx(60.0f));
    CHECK(textOf(ids::humanise, 0.2f) == "20 %");
    CHECK(textOf(ids::decayScale, 2.0f) == "x2.00");
    CHECK(textOf(ids::gain, -6.0f) == "-6.0 dB");
    // Any value's text reads back to a value with the same text.
    for (auto* param : p.getParameters())
        for (const float normalised : {0.0f, 0.13f, 0.5f, 0.77f, 1.0f})
        {
            const auto shown = param->getText(normalised, 100);
            INFO(param->getName(100) << " at " << normalised << ": " << shown);
            CHECK(shown.isNotEmpty());
            CHECK(param->getText(param->getValueForText(shown), 100) == shown);
        }
}

TEST_CASE("ParameterReader reads each parameter into its own engine field", "[plugin]")
{
    JawariAudioProcessor p;
    const std::pair<const char*, float> values[] = {{ids::stringType, 2.0f},
                                                    {ids::obstacleShape, 1.0f},
                                                    {ids::obstaclePosition, 0.3f},
                                                    {ids::obstacleHeight, -0.25f},
                                                    {ids::obstacleStiffness, 12.0f},
                                                    {ids::obstacleExponent, 1.5f},
                                                    {ids::obstacleWidth, 2.5f},
                                                    {ids::bridgeCurvature, 8.0f},
                                                    {ids::pluckPosition, 0.2f},
                                                    {ids::pickupPosition, 0.9f},
                                                    {ids::decayScale, 2.0f},
                                                    {ids::airDamping, 3.0f},
                                                    {ids::viscoelasticLoss, 0.01f},
                                                    {ids::thermoelasticLoss, 2.5f},
                                                    {ids::inharmonicity, 1e-4f},
                                                    {ids::release, 1.5f},
                                                    {ids::quality, 2.0f},
                                                    {ids::method, 1.0f},
                                                    {ids::gain, -6.0f},
                                                    {ids::bendRange, 7.0f},
                                                    {ids::drone, 1.0f},
                                                    {ids::droneTonic, 60.0f},
                                                    {ids::droneFirst, 2.0f},
                                                    {ids::droneTempo, 90.0f},
                                                    {ids::humanise, 0.5f},
                                                    {ids::droneStrength, 0.35f},
                                                    {ids::droneTuning, 1.0f},
                                                    {ids::droneSaHz, 146.5f},
                                                    {ids::droneFine1, -3.5f},
                                                    {ids::droneFine2, 1.5f},
                                                    {ids::droneFine3, 2.5f},
                                                    {ids::droneFine4, -12.0f},
                                                    {ids::mpe, 1.0f},
                                                    {ids::mpeBendRange, 24.0f},
                                                    {ids::stereoWidth, 0.25f},
                                                    {ids::secondCore, 1.0f},
                                                    {ids::polarisations, 1.0f},
                                                    {ids::thread, 1.0f},
                                                    {ids::threadPosition, 3.5f},
                                                    {ids::threadDiameter, 0.3f},
                                                    {ids::threadModel, 1.0f},
                                                    {ids::threadStiffness, 50.0f},
                                                    {ids::threadDamping, 3.0f},
                                                    {ids::pluckStyle, 1.0f},
                                                    {ids::body, 1.0f},
                                                    {ids::bodyMix, 0.4f},
                                                    {ids::bodyTuning, 1.5f},
                                                    {ids::bodyDamping, 2.0f},
                                                    {ids::sympathetic, 7.0f},
                                                    {ids::sympatheticScale, 9.0f},
                                                    {ids::sympatheticIntonation, 1.0f},
                                                    {ids::sympatheticDamping, 4.0f},
                                                    {ids::sympatheticLevel, 0.3f},
                                                    {ids::sympatheticJawari, 1.0f},
                                                    {ids::voices, 3.0f}};
    REQUIRE(std::size(values) == kParameterCount);
    for (const auto& [id, value] : values)
        setParameter(p, id, value);
    std::array<std::atomic<float>, kDampingCurvePoints> curve;
    for (auto& point : curve)
        point.store(2.0f);

    const ParameterReader reader(p.parameters());
    const auto s = reader.structure(44100.0);
    CHECK(s.stringType == 2);
    CHECK(s.shape == ObstacleShape::parabola);
    CHECK(s.obstaclePosition == Approx(0.3).epsilon(1e-4));
    CHECK(s.obstacleWidth == Approx(2.5e-3).epsilon(1e-4));
    CHECK(s.curvature == Approx(8.0).epsilon(1e-4));
    CHECK(s.pluckPosition == Approx(0.2).epsilon(1e-4));
    CHECK(s.pickupPosition == Approx(0.9).epsilon(1e-4));
    CHECK(s.inharmonicity == Approx(1e-4).epsilon(1e-4));
    CHECK(s.releaseSeconds == Approx(1.5).epsilon(1e-4));
    CHECK(s.quality == 2);
    CHECK(s.method == ContactMethod::quadratised);
    CHECK(s.polarisations == 2);
    CHECK(s.thread);
    CHECK(s.threadOffset == Approx(3.5e-3).epsilon(1e-4));
    CHECK(s.threadDiameter == Approx(0.3e-3).epsilon(1e-4));
    CHECK(s.threadModel == ThreadModel::contact);
    CHECK(s.threadStiffness == Approx(5e4).epsilon(1e-4));
    CHECK(s.threadDamping == Approx(3.0).epsilon(1e-4));
    CHECK(s.pluck == PluckStyle::soft);
    CHECK(s.body == BodyChoice::tanpura);
    CHECK(s.bodyTuning == Approx(1.5).epsilon(1e-4));
    CHECK(s.bodyDamping == Approx(2.0).epsilon(1e-4));
    CHECK(s.sympatheticStrings == 7);
    CHECK(s.sympatheticJawari);
    CHECK(s.hostRateHz == 44100.0);

    const auto c = reader.controls(curve);
    CHECK(c.obstacleHeight == Approx(-0.25e-3).epsilon(1e-4));
    CHECK(c.stiffness == Approx(1e12).epsilon(1e-4));
    CHECK(c.exponent == Approx(1.5).epsilon(1e-4));
    CHECK(c.decayScale == Approx(2.0).epsilon(1e-4));
    CHECK(c.airScale == Approx(3.0).epsilon(1e-4));
    CHECK(c.deltaVe == Approx(0.01).epsilon(1e-4));
    CHECK(c.qTeInv == Approx(2.5e-4).epsilon(1e-4));
    CHECK(c.dampingCurve[0] == 2.0);
    CHECK(c.gainDb == Approx(-6.0).epsilon(1e-4));
    CHECK(c.bendRangeSemitones == Approx(7.0));
    CHECK(c.midiVoices == 3);
    CHECK(c.drone);
    CHECK(c.droneTonic == 60);
    CHECK(c.droneFirst == 2);
    CHECK(c.droneTempo == Approx(90.0).epsilon(1e-4));
    CHECK(c.humanise == Approx(0.5).epsilon(1e-4));
    CHECK(c.droneStrength == Approx(0.35).epsilon(1e-4));
    CHECK(c.droneTuning == DroneTuning::equal);
    CHECK(c.droneSaHz == Approx(146.5).epsilon(1e-4));
    CHECK(c.droneFineCents[0] == Approx(-3.5).epsilon(1e-4));
    CHECK(c.droneFineCents[1] == Approx(1.5).epsilon(1e-4));
    CHECK(c.droneFineCents[2] == Approx(2.5).epsilon(1e-4));
    CHECK(c.droneFineCents[3] == Approx(-12.0).epsilon(1e-4));
    CHECK(reader.midi().mpe);
    CHECK(reader.midi().mpeBendRange == Approx(24.0));
    CHECK(c.stereoWidth == Approx(0.25).epsilon(1e-4));
    CHECK(c.bodyMix == Approx(0.4).epsilon(1e-4));
    CHECK(c.sympatheticScale == SympatheticScale::purvi);
    CHECK(c.sympatheticIntonation == SympatheticIntonation::keyboard);
    CHECK(c.sympatheticDamping == Approx(4.0).epsilon(1e-4));
    CHECK(c.sympatheticLevel == Approx(0.3).epsilon(1e-4));
}

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
            float value = std::uniform_real_distribution<float>(0.0f, 1.0f)(rng);
            // Quality "paper" would make this test slow; the penalty method blows up by design (its
            // guard mutes it: VoiceTests) and the quadratised one went past +12 dBFS on stiff frets
            // of a high exponent; a gain above 0 dB may take loud notes past the output guard's +12 dBFS (the
            // extremes test below takes it to +12 dB), and so does an obstacle above the string's
            // rest line, which launches a string plucked into it with the energy its contact holds.
            // Every other value of everything goes.
            if (auto* ranged = dynamic_cast<juce::RangedAudioParameter*>(param); ranged != nullptr)
            {
                const auto id = ranged->getParameterID();
                if (id == ids::quality)
                    continue;
                if (id == ids::gain || id == ids::obstacleHeight)
                    value = ranged->convertTo0to1(std::min(ranged->convertFrom0to1(value), 0.0f));
                if (id == ids::method)
                {
                    const auto method = kContactMethods[size_t(std::lround(ranged->convertFrom0to1(value)))].method;
                    if (method == ContactMethod::penalty || method == ContactMethod::quadratised)
                        continue;
                }
            }
            param->setValueNotifyingHost(value);
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
        // Keys pressed on the editor's keyboard between blocks (the message thread's work, not counted).
        auto pressKey = [&](int note, bool down) {
            test::countAllocationsOnThisThread(false);
            if (down)
                p.keyboardState().noteOn(1, note, 0.8f);
            else
                p.keyboardState().noteOff(1, note, 0.0f);
            test::countAllocationsOnThisThread(true);
        };
        {
            test::CountAllocations guard;
            for (int b = 0; b < 200; ++b)
            {
                if (b % 10 == 5)
                    pressKey(60 + (b / 20) % 12, b % 20 == 5);
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
                if (b == 120 && body)  // fewer sympathetic strings, on their jawari: a new pack, built off this thread
                {
                    test::countAllocationsOnThisThread(false);
                    setParameter(p, ids::sympathetic, 5.0f);
                    setParameter(p, ids::sympatheticJawari, 1.0f);
                    REQUIRE(p.waitForBuilds());
                    test::countAllocationsOnThisThread(true);
                }
                if (b == 160)
                    tasksBefore160 = worker.tasks.load();
                if ((b == 140 || b == 160) && body)  // another body, then none: the motion carried across
                {
                    test::countAllocationsOnThisThread(false);
                    setParameter(p, ids::body, b == 140 ? 2.0f : 0.0f);
                    REQUIRE(p.waitForBuilds());
                    test::countAllocationsOnThisThread(true);
                    midi.addEvent(juce::MidiMessage::noteOn(1, 50, juce::uint8(100)), 0);
                }
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

TEST_CASE("setStateInformation survives empty, truncated, random and older-version data", "[plugin]")
{
    JawariAudioProcessor p;
    setParameter(p, ids::gain, -6.0f);
    juce::MemoryBlock good;
    p.getStateInformation(good);
    std::mt19937 rng(3);
    // Empty, null and truncated: nothing changes.
    p.setStateInformation(nullptr, 0);
    p.setStateInformation(good.getData(), 0);
    for (size_t cut = 1; cut < good.getSize(); cut += 7)
        p.setStateInformation(good.getData(), int(cut));
    CHECK(parameterValue(p, ids::gain) == Approx(-6.0f));
    // Thousands of random blobs, some behind a valid JUCE XML header so the parser sees them.
    std::vector<char> blob;
    for (int i = 0; i < 3000; ++i)
    {
        blob.resize(size_t(1 + rng() % 600));
        for (auto& c : blob)
            c = char(rng());
        if (i % 2 == 0 && blob.size() > 8)
        {
            const juce::uint32 magic = 0x21324356, size = juce::uint32(blob.size() - 8);
            std::memcpy(blob.data(), &magic, 4);
            std::memcpy(blob.data() + 4, &size, 4);
        }
        p.setStateInformation(blob.data(), int(blob.size()));
    }
    // What libFuzzer found under ASan: a header, then UTF-8 lead bytes with no continuation (JUCE's
    // parser read past the end of it). Kept as a regression file; and the same shape built here.
    {
        juce::MemoryBlock crash;
        REQUIRE(juce::File(JAWARI_TESTS_DIR "/Fuzz/regressions/state-invalid-utf8.bin").loadFileAsData(crash));
        p.setStateInformation(crash.getData(), int(crash.getSize()));
        // And a value with an exponent too long for JUCE's number reader (signed overflow in it).
        juce::MemoryBlock longExponent;
        REQUIRE(juce::File(JAWARI_TESTS_DIR "/Fuzz/regressions/state-long-exponent.bin").loadFileAsData(longExponent));
        juce::MemoryBlock keep;
        p.getStateInformation(keep);
        p.setStateInformation(longExponent.getData(), int(longExponent.getSize()));
        p.setStateInformation(keep.getData(), int(keep.getSize()));
        // And a processing instruction followed by text inside an element (JUCE's XML reader
        // looped for ever on it).
        juce::MemoryBlock instruction;
        REQUIRE(juce::File(JAWARI_TESTS_DIR "/Fuzz/regressions/state-processing-instruction.bin")
                    .loadFileAsData(instruction));
        p.setStateInformation(instruction.getData(), int(instruction.getSize()));
        std::vector<char> cut = {'V', 'C', '2', '!', 6, 0, 0, 0, '<', 'a', '>', char(0xeb), char(0xeb), char(0xeb)};
        p.setStateInformation(cut.data(), int(cut.size()));
        CHECK(parameterValue(p, ids::gain) == Approx(-6.0f));
    }
    // Mangled values inside a real state: NaN, infinities, text, out of range, unknown ids.
    for (const char* bad : {"nan", "inf", "-inf", "1e400", "banana", "", "-1e30", "1e30"})
    {
        juce::ValueTree tree = p.state();
        auto params = tree.getChildWithName("Parameters");
        for (int i = 0; i < params.getNumChildren(); ++i)
            params.getChild(i).setProperty("value", bad, nullptr);
        tree.getChildWithName("DampingCurve").setProperty("p3", bad, nullptr);
        juce::MemoryBlock mangled;
        juce::AudioProcessor::copyXmlToBinary(*tree.createXml(), mangled);
        p.setStateInformation(mangled.getData(), int(mangled.getSize()));
        for (auto* param : p.getParameters())
        {
            auto* ranged = dynamic_cast<juce::RangedAudioParameter*>(param);
            INFO(ranged->getParameterID() << " after value " << bad);
            CHECK(ranged->getValue() == Approx(ranged->getDefaultValue()));
        }
        CHECK(p.dampingCurvePoint(3) == 1.0f);
    }
    // An older state (version 1: no damping curve) with one parameter set: read, the rest default.
    juce::ValueTree old("JawariState");
    old.setProperty("version", 1, nullptr);
    juce::ValueTree params("Parameters");
    juce::ValueTree gain("Param");
    gain.setProperty("id", ids::gain, nullptr);
    gain.setProperty("value", -12.0, nullptr);
    params.appendChild(gain, nullptr);
    old.appendChild(params, nullptr);
    juce::MemoryBlock oldBlob;
    juce::AudioProcessor::copyXmlToBinary(*old.createXml(), oldBlob);
    p.setDampingCurvePoint(0, 4.0f);
    p.setStateInformation(oldBlob.getData(), int(oldBlob.getSize()));
    CHECK(parameterValue(p, ids::gain) == Approx(-12.0f));
    CHECK(parameterValue(p, ids::obstacleStiffness) == Approx(13.0f));
    CHECK(p.dampingCurvePoint(0) == 1.0f);
    // And it still plays.
    prepare(p, 48000.0, 256);
    const auto y = renderNote(p, 48000.0, 256, 0.3);
    CHECK(peakOf(y) > 1e-3);
    CHECK(peakOf(y) <= 1.0);
}

TEST_CASE("A state file that is not UTF-8, not XML or not a Jawari state is refused with its reason", "[plugin]")
{
    JawariAudioProcessor p;
    setParameter(p, ids::gain, -6.0f);
    const auto xml = p.state().toXmlString();
    setParameter(p, ids::gain, -3.0f);
    struct Case
    {
        std::string bytes, expected;
    };
    const std::vector<Case> cases = {
        {"<JawariState a=\"\xe9\"/>", "not valid UTF-8"},
        {"<JawariState><Parameters>", "not XML"},
        {" \n", "not XML"},
        {"<Other/>", "its root element is <Other>, not <JawariState>"},
        {"<JawariState><?p?>x</JawariState>", "a processing instruction"},
    };
    juce::TemporaryFile file(".jawaripreset");
    for (const auto& c : cases)
    {
        REQUIRE(file.getFile().replaceWithData(c.bytes.data(), c.bytes.size()));
        const auto result = p.loadUserPreset(file.getFile());
        INFO(c.bytes << ": " << result.getErrorMessage());
        CHECK(result.failed());
        CHECK(result.getErrorMessage().contains(c.expected));
        CHECK(parameterValue(p, ids::gain) == Approx(-3.0f));
    }
    CHECK(p.loadUserPreset(file.getFile().getSiblingFile("missing.jawaripreset"))
              .getErrorMessage()
              .contains("no such file"));
    // A good state behind a byte order mark, as a text editor may save it.
    const std::string marked = "\xEF\xBB\xBF" + xml.toStdString();
    REQUIRE(file.getFile().replaceWithData(marked.data(), marked.size()));
    CHECK(p.loadUserPreset(file.getFile()).wasOk());
    CHECK(parameterValue(p, ids::gain) == Approx(-6.0f));
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

TEST_CASE("The editor opens without a window and draws the sounding string", "[plugin]")
{
    JawariAudioProcessor p;
    setParameter(p, ids::quality, 0.0f);
    prepare(p, 48000.0, 512);
    renderNote(p, 48000.0, 512, 0.2);
    std::unique_ptr<juce::AudioProcessorEditor> editor(p.createEditorIfNeeded());
    REQUIRE(editor != nullptr);
    editor->setSize(1200, 800);
    InstrumentSnapshot s;
    CHECK(p.instrument().snapshots().read(s));
    CHECK(s.activeStrings == 1);
    float largest = 0.0f;
    for (float u : s.shape)
        largest = std::max(largest, std::abs(u));
    CHECK(largest > 1e-5f);  // the string is drawn displaced
    const auto image = editor->createComponentSnapshot(editor->getLocalBounds());
    CHECK(image.getWidth() == 1200);
    p.editorBeingDeleted(editor.get());
}

namespace
{
// The editor's descendant whose component ID is `id`, or null.
juce::Component* findById(juce::Component& root, const juce::String& id)
{
    if (root.getComponentID() == id)
        return &root;
    for (auto* child : root.getChildren())
        if (auto* found = findById(*child, id))
            return found;
    return nullptr;
}

template <typename T>
T* findOfType(juce::Component& root)
{
    if (auto* found = dynamic_cast<T*>(&root))
        return found;
    for (auto* child : root.getChildren())
        if (auto* found = findOfType<T>(*child))
            return found;
    return nullptr;
}

juce::String tooltipOf(juce::Component* c)
{
    auto* client = dynamic_cast<juce::TooltipClient*>(c);
    return client != nullptr ? client->getTooltip() : juce::String();
}
}  // namespace

TEST_CASE("Every parameter has a control in the editor with a tooltip, and a keyboard and Pluck button play",
          "[plugin]")
{
    JawariAudioProcessor p;
    std::unique_ptr<juce::AudioProcessorEditor> editor(p.createEditorIfNeeded());
    REQUIRE(editor != nullptr);
    for (const char* id : kParameterIds)
    {
        INFO(id);
        auto* control = findById(*editor, id);
        REQUIRE(control != nullptr);
        CHECK(control->isVisible());
        CHECK(control->getWidth() > 20);
        CHECK(tooltipOf(control).length() > 10);
    }
    auto* keyboard = findOfType<juce::MidiKeyboardComponent>(*editor);
    REQUIRE(keyboard != nullptr);
    CHECK(keyboard->getWidth() > 500);
    CHECK(tooltipOf(keyboard).isNotEmpty());
    auto* pluck = dynamic_cast<juce::Button*>(findById(*editor, "pluck"));
    REQUIRE(pluck != nullptr);
    CHECK(pluck->getButtonText() == "Pluck C#3");
    CHECK(tooltipOf(pluck).isNotEmpty());

    // The Pluck button holds the drone's tonic while it is down.
    const int tonic = 49;
    prepare(p, 48000.0, 512);
    pluck->setState(juce::Button::buttonDown);
    CHECK(p.keyboardState().isNoteOn(1, tonic));
    const auto y = render(p, 48000.0, 512, 0.5);
    CHECK(peakOf(y) > 1e-3);
    const double f0 = 440.0 * std::pow(2.0, (tonic - 69) / 12.0);
    // The tonic and not a neighbour (a semitone is 6 %); the default bridge, 6 mm from the end,
    // raises this low string a little (0.3 %).
    CHECK(peakFrequency(y, 48000.0, 0.9 * f0, 1.1 * f0, 4800) == Approx(f0).epsilon(1e-2));
    pluck->setState(juce::Button::buttonNormal);
    CHECK_FALSE(p.keyboardState().isNoteOn(1, tonic));
    p.editorBeingDeleted(editor.get());
}

TEST_CASE("A note pressed on the keyboard state sounds in tune and stops on release", "[plugin]")
{
    JawariAudioProcessor p;
    setParameter(p, ids::quality, 0.0f);
    prepare(p, 48000.0, 256);
    CHECK(peakOf(render(p, 48000.0, 256, 0.1)) == 0.0);
    p.keyboardState().noteOn(1, 69, 100.0f / 127.0f);
    const auto held = render(p, 48000.0, 256, 0.6);
    CHECK(peakOf(held) > 1e-3);
    CHECK(peakOf(held) <= 1.0);
    const double f = peakFrequency(held, 48000.0, 400.0, 480.0, 4800);
    INFO("f0 " << f);
    CHECK(std::abs(f / 440.0 - 1.0) < 2e-3);
    // Released: the default 0.4 s release takes it 60 dB down; after 1.5 s it is far below.
    p.keyboardState().noteOff(1, 69, 0.0f);
    const auto released = render(p, 48000.0, 256, 1.5);
    const std::vector<double> tail(released.end() - 4800, released.end());
    CHECK(peakOf(tail) < 1e-3 * peakOf(held));
}

TEST_CASE("A Scala scale tunes the keyboard, travels in the state, and a bad one is refused", "[plugin]")
{
    const juce::String justScale =
        "5-limit just\n12\n16/15\n9/8\n6/5\n5/4\n4/3\n45/32\n3/2\n8/5\n5/3\n9/5\n15/8\n2/1\n";
    const juce::String a440 = "12\n0\n127\n60\n69\n440.0\n12\n0\n1\n2\n3\n4\n5\n6\n7\n8\n9\n10\n11\n";
    JawariAudioProcessor p;
    prepare(p, 48000.0, 512);
    setParameter(p, ids::obstacleHeight, -5.0f);  // the bridge out of reach: a free string, a clean pitch
    REQUIRE(p.waitForBuilds());
    CHECK(p.setKeyboardTuning(justScale, a440).isEmpty());
    CHECK(p.keyboardTuningName() == "5-limit just");
    // G4 (67) is C 3/2 = 396 Hz in this tuning (392.0 Hz in equal temperament).
    const auto y = renderNote(p, 48000.0, 512, 1.5, 67);
    const double f = peakFrequency(y, 48000.0, 380.0, 410.0, 4800, y.size() - 4800);
    INFO("G4 plays " << f << " Hz");
    CHECK(std::abs(f / 396.0 - 1.0) < 0.002);

    // The state carries the scale: a second processor restores it.
    juce::MemoryBlock saved;
    p.getStateInformation(saved);
    JawariAudioProcessor q;
    q.setStateInformation(saved.getData(), int(saved.getSize()));
    CHECK(q.keyboardTuningName() == "5-limit just");

    // A bad scale is refused with its problem named, and the tuning stays.
    const auto error = p.setKeyboardTuning("broken\n3\n100.0\n", {});
    INFO("error: " << error);
    CHECK(error.contains("announces 3 pitches but gives 1"));
    CHECK(p.keyboardTuningName() == "5-limit just");
    // The editor shows the tuning on its scale button (which loads .scl files).
    {
        std::unique_ptr<juce::AudioProcessorEditor> editor(p.createEditorIfNeeded());
        REQUIRE(editor != nullptr);
        bool shown = false;
        for (auto* child : editor->getChildren())
            if (auto* button = dynamic_cast<juce::TextButton*>(child))
                shown = shown || button->getButtonText() == "Scale: 5-limit just";
        CHECK(shown);
        p.editorBeingDeleted(editor.get());
    }
    // Back to equal temperament.
    CHECK(p.setKeyboardTuning({}, {}).isEmpty());
    CHECK(p.keyboardTuningName() == "equal temperament");
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

