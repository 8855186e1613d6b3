// The plugin's parameters: their order, names and defaults, their values in a player's units, and
// each read into its own engine field.

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
#include <random>
#include <string>
#include <thread>
#include <utility>
#include <vector>

using namespace jawari;
using namespace jawari::plugin;
using namespace jawari::plugin_tests;

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
