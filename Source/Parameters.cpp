#include "Parameters.h"

#include "ParameterText.h"
#include "physics/contact/ContactMethod.h"
#include "realtime/voice/Quality.h"
#include "realtime/instrument/VoicePack.h"

#include <algorithm>
#include <cmath>
#include <functional>

namespace jawari::plugin
{
namespace
{
using Range = juce::NormalisableRange<float>;
using Layout = juce::AudioProcessorValueTreeState::ParameterLayout;

// The engine's defaults: each parameter's default is the engine's, in the parameter's unit.
constexpr InstrumentStructure kStructureDefaults{};
constexpr InstrumentControls kControlDefaults{};

// Parameters shown in other units than the engine's.
constexpr double kMetresPerMillimetre = 1e-3;  // obstacle height and width: mm
constexpr double kThermoelasticUnit = 1e-4;    // thermoelastic loss: 1/Q in units of 1e-4
constexpr double kNewtonsPerKilonewton = 1e3;  // the thread's stiffness: kN/m

Range skewed(float lo, float hi, float centre)
{
    Range r(lo, hi);
    r.setSkewForCentre(centre);
    return r;
}

// How a parameter's value reads as text, with its unit, and how typed text reads back (ParameterText).
struct Display
{
    std::function<juce::String(double)> toText;
    std::function<double(const juce::String&)> fromText;
};

// "1.00 mm": a number and its unit.
Display inUnit(const char* unit, int decimals)
{
    const juce::String suffix = *unit == 0 ? juce::String() : " " + juce::String(unit);
    return {[decimals, suffix](double v) { return text::fixed(v, decimals) + suffix; }, text::leadingNumber};
}

Display asMultiplier(int decimals)
{
    return {[decimals](double v) { return text::multiplier(v, decimals); }, text::leadingNumber};
}

Display asPercent()
{
    return {text::percent, text::parsePercent};
}

// A point on the string in mm from the bridge end, on the string `string` selects.
Display asPosition(const juce::AudioParameterChoice& string)
{
    auto length = [&string] {
        return kStringTypes[std::clamp(string.getIndex(), 0, kStringTypeCount - 1)].lengthMetres;
    };
    return {[length](double v) { return text::position(v, length()); },
            [length](const juce::String& t) { return text::parsePosition(t, length()); }};
}

// A value held in units of `unit` shown as the number itself ("1.38e-4" for 1.38 units of 1e-4).
// Typed text is that number, or (when that would lie above `largest` units) the held value.
Display asScientific(double unit, int decimals, double largest)
{
    return {[unit, decimals](double v) { return text::scientific(v * unit, decimals); },
            [unit, largest](const juce::String& t) {
                const double typed = text::leadingNumber(t);
                return typed / unit > largest ? typed : typed / unit;
            }};
}

std::unique_ptr<juce::AudioParameterFloat> number(const char* id, const char* name, Range range, double value,
                                                  Display display)
{
    auto toText = [f = std::move(display.toText)](float v, int maximumLength) {
        const auto s = f(v);
        return maximumLength > 0 ? s.substring(0, maximumLength) : s;
    };
    auto fromText = [f = std::move(display.fromText)](const juce::String& t) { return static_cast<float>(f(t)); };
    return std::make_unique<juce::AudioParameterFloat>(juce::ParameterID{id, 1}, name, range, static_cast<float>(value),
                                                       juce::AudioParameterFloatAttributes()
                                                           .withStringFromValueFunction(std::move(toText))
                                                           .withValueFromStringFunction(std::move(fromText)));
}

std::unique_ptr<juce::AudioParameterChoice> choice(const char* id, const char* name, const juce::StringArray& choices,
                                                   int defaultIndex)
{
    return std::make_unique<juce::AudioParameterChoice>(juce::ParameterID{id, 1}, name, choices, defaultIndex);
}

// The choices of a parameter that indexes one of the engine's tables, named as the table names them.
template <typename Table, typename Name>
juce::StringArray namesOf(const Table& table, Name name)
{
    juce::StringArray names;
    for (const auto& entry : table)
        names.add(name(entry));
    return names;
}

int contactMethodIndex(ContactMethod method)
{
    for (int i = 0; i < playerContactMethodCount(); ++i)
        if (kContactMethods[size_t(i)].method == method)
            return i;
    return 0;
}

// The string, and the obstacle it buzzes against. Returns the string's choice, whose length the
// positions along it are shown in.
const juce::AudioParameterChoice& addStringAndObstacle(Layout& layout)
{
    const auto& s = kStructureDefaults;
    const auto& c = kControlDefaults;
    auto stringChoice = choice(ids::stringType, "String",
                               namesOf(kStringTypes, [](const StringType& t) { return t.name; }), s.stringType);
    const auto& string = *stringChoice;
    layout.add(std::move(stringChoice));
    layout.add(choice(ids::obstacleShape, "Obstacle shape", juce::StringArray{"point", "parabolic bridge", "frets"},
                      static_cast<int>(s.shape)));
    // A tanpura's bridge near the end of the string by default (the engine's structure defaults to the centre).
    layout.add(number(ids::obstaclePosition, "Obstacle position", Range(0.005f, 0.995f), 0.006f, asPosition(string)));
    layout.add(number(ids::obstacleHeight, "Obstacle height", Range(-5.0f, 1.0f, 0.0001f),
                      c.obstacleHeight / kMetresPerMillimetre, inUnit("mm", 2)));
    // The stiffness reads in the unit the exponent gives it, N/m^(1+alpha).
    auto exponent =
        number(ids::obstacleExponent, "Obstacle exponent", Range(1.0f, 4.0f, 0.01f), c.exponent, inUnit("", 2));
    const auto& alpha = *exponent;
    layout.add(number(ids::obstacleStiffness, "Obstacle stiffness", Range(6.0f, 16.0f, 0.01f), std::log10(c.stiffness),
                      {[&alpha](double v) { return text::stiffness(v, alpha.get()); }, text::parseStiffness}));
    layout.add(std::move(exponent));
    layout.add(number(ids::obstacleWidth, "Obstacle width", skewed(0.1f, 50.0f, 3.0f),
                      s.obstacleWidth / kMetresPerMillimetre, inUnit("mm", 2)));
    layout.add(
        number(ids::bridgeCurvature, "Bridge curvature", skewed(0.0f, 100.0f, 5.0f), s.curvature, inUnit("/m", 2)));
    return string;
}

// Where the string is plucked and heard, and how it loses energy.
void addPointsAndDamping(Layout& layout, const juce::AudioParameterChoice& string)
{
    const auto& s = kStructureDefaults;
    const auto& c = kControlDefaults;
    layout.add(number(ids::pluckPosition, "Pluck position", Range(0.02f, 0.98f), s.pluckPosition, asPosition(string)));
    // The paper's pickup, 0.992 m on its 1.002 m string.
    layout.add(
        number(ids::pickupPosition, "Pickup position", Range(0.01f, 0.995f), 0.992f / 1.002f, asPosition(string)));
    layout.add(number(ids::decayScale, "Decay scale", skewed(0.1f, 10.0f, 1.0f), c.decayScale, asMultiplier(2)));
    layout.add(number(ids::airDamping, "Air damping", skewed(0.0f, 10.0f, 1.0f), c.airScale, asMultiplier(2)));
    layout.add(
        number(ids::viscoelasticLoss, "Viscoelastic loss", Range(0.0f, 0.05f, 0.0001f), c.deltaVe, inUnit("", 4)));
    layout.add(number(ids::thermoelasticLoss, "Thermoelastic loss", Range(0.0f, 10.0f, 0.01f),
                      c.qTeInv / kThermoelasticUnit, asScientific(kThermoelasticUnit, 2, 10.0)));
    layout.add(number(ids::inharmonicity, "Inharmonicity", skewed(0.0f, 1e-3f, 5e-5f), s.inharmonicity,
                      asScientific(1.0, 2, 1e-3)));
    layout.add(number(ids::release, "Release", skewed(0.05f, 5.0f, 0.5f), s.releaseSeconds, inUnit("s", 2)));
}

// How much model runs and how it finds the contact; what comes out.
void addQualityAndOutput(Layout& layout)
{
    const auto& s = kStructureDefaults;
    const auto& c = kControlDefaults;
    layout.add(choice(ids::quality, "Quality",
                      namesOf(kQualitySettings, [](const QualitySetting& q) { return q.name; }), s.quality));
    juce::StringArray methods;
    for (int i = 0; i < playerContactMethodCount(); ++i)
        methods.add(kContactMethods[size_t(i)].playerName);
    layout.add(choice(ids::method, "Contact method", methods, contactMethodIndex(s.method)));
    layout.add(number(ids::gain, "Output gain", Range(-48.0f, 12.0f, 0.1f), c.gainDb, inUnit("dB", 1)));
    layout.add(number(ids::bendRange, "Pitch bend range", Range(0.0f, 12.0f, 1.0f), c.bendRangeSemitones,
                      inUnit("semitones", 0)));
}

// The tanpura drone.
void addDrone(Layout& layout)
{
    const auto& c = kControlDefaults;
    layout.add(std::make_unique<juce::AudioParameterBool>(juce::ParameterID{ids::drone, 1}, "Drone", c.drone));
    layout.add(std::make_unique<juce::AudioParameterInt>(
        juce::ParameterID{ids::droneTonic, 1}, "Drone tonic (Sa)", 36, 72, c.droneTonic,
        juce::AudioParameterIntAttributes()
            .withStringFromValueFunction([](int note, int) { return text::noteName(note); })
            .withValueFromStringFunction(text::parseNote)));
    layout.add(choice(ids::droneFirst, "First string", juce::StringArray{"Pa", "Ma", "Ni", "Sa"}, c.droneFirst));
    layout.add(
        number(ids::droneTempo, "Drone tempo", Range(20.0f, 200.0f, 0.1f), c.droneTempo, inUnit("plucks/min", 1)));
    layout.add(number(ids::humanise, "Humanise", Range(0.0f, 1.0f, 0.001f), c.humanise, asPercent()));
    layout.add(number(ids::droneStrength, "Drone strength", Range(0.0f, 1.0f, 0.001f), c.droneStrength, asPercent()));
}

// How the drone is tuned.
void addDroneTuning(Layout& layout)
{
    const auto& c = kControlDefaults;
    layout.add(choice(ids::droneTuning, "Drone tuning", juce::StringArray{"just", "equal temperament"},
                      static_cast<int>(c.droneTuning)));
    // 0: the tonic note sets Sa.
    layout.add(number(ids::droneSaHz, "Drone Sa frequency", Range(0.0f, 1000.0f, 0.01f), c.droneSaHz,
                      {[](double v) { return v > 0.0 ? text::fixed(v, 2) + " Hz" : juce::String("from Sa note"); },
                       text::leadingNumber}));
    const char* fine[] = {ids::droneFine1, ids::droneFine2, ids::droneFine3, ids::droneFine4};
    const char* names[] = {"Drone fine tune: first string", "Drone fine tune: Sa", "Drone fine tune: second Sa",
                           "Drone fine tune: low Sa"};
    for (size_t k = 0; k < std::size(fine); ++k)
        layout.add(number(fine[k], names[k], Range(-50.0f, 50.0f, 0.1f), c.droneFineCents[k], inUnit("cents", 1)));
}

// How MIDI is read.
void addMidi(Layout& layout)
{
    const MidiSettings m;
    layout.add(std::make_unique<juce::AudioParameterBool>(juce::ParameterID{ids::mpe, 1}, "MPE", m.mpe));
    layout.add(number(ids::mpeBendRange, "MPE note bend range", Range(1.0f, 96.0f, 1.0f), m.mpeBendRange,
                      inUnit("semitones", 0)));
}

// The body under the bridge (docs/design.md section 1, "The body") and how the strings are plucked.
void addBody(Layout& layout)
{
    const auto& s = kStructureDefaults;
    layout.add(choice(ids::pluckStyle, "Pluck", juce::StringArray{"sharp", "soft"}, static_cast<int>(s.pluck)));
    juce::StringArray bodies;
    for (const char* name : kBodyNames)
        bodies.add(name);
    layout.add(choice(ids::body, "Body", bodies, static_cast<int>(s.body)));
    layout.add(number(ids::bodyMix, "Body mix", Range(0.0f, 1.0f, 0.001f), float(kControlDefaults.bodyMix),
                      asPercent()));
    layout.add(number(ids::bodyTuning, "Body tuning", skewed(0.5f, 2.0f, 1.0f), float(s.bodyTuning), asMultiplier(2)));
    layout.add(
        number(ids::bodyDamping, "Body damping", skewed(0.25f, 4.0f, 1.0f), float(s.bodyDamping), asMultiplier(2)));
}

// The sitar's sympathetic strings on the body (SympatheticStrings.h), tuned from the drone's Sa.
void addSympathetic(Layout& layout)
{
    const auto& c = kControlDefaults;
    layout.add(std::make_unique<juce::AudioParameterInt>(juce::ParameterID{ids::sympathetic, 1}, "Sympathetic strings",
                                                         0, kMaxSympatheticStrings,
                                                         kStructureDefaults.sympatheticStrings));
    juce::StringArray scales;
    for (const char* name : kSympatheticScaleNames)
        scales.add(name);
    layout.add(choice(ids::sympatheticScale, "Sympathetic tuning", scales, static_cast<int>(c.sympatheticScale)));
    layout.add(choice(ids::sympatheticIntonation, "Sympathetic intonation", juce::StringArray{"just", "keyboard"},
                      static_cast<int>(c.sympatheticIntonation)));
    layout.add(number(ids::sympatheticDamping, "Sympathetic damping", skewed(0.25f, 20.0f, 1.0f),
                      float(c.sympatheticDamping), asMultiplier(2)));
    layout.add(number(ids::sympatheticLevel, "Sympathetic level", Range(0.0f, 1.0f, 0.001f),
                      float(c.sympatheticLevel), asPercent()));
    layout.add(std::make_unique<juce::AudioParameterBool>(juce::ParameterID{ids::sympatheticJawari, 1},
                                                          "Sympathetic jawari", kStructureDefaults.sympatheticJawari));
}

int rounded(float value)
{
    return static_cast<int>(std::lround(value));
}
}  // namespace

juce::AudioProcessorValueTreeState::ParameterLayout createParameterLayout()
{
    // In the order of kParameterIds (tested).
    Layout layout;
    const auto& string = addStringAndObstacle(layout);
    addPointsAndDamping(layout, string);
    addQualityAndOutput(layout);
    addDrone(layout);
    addDroneTuning(layout);
    addMidi(layout);
    layout.add(
        number(ids::stereoWidth, "Stereo width", Range(0.0f, 1.0f, 0.01f), kControlDefaults.stereoWidth, asPercent()));
    // Off by default: a second core only helps where the host leaves one free (StringWorker.h).
    layout.add(std::make_unique<juce::AudioParameterBool>(juce::ParameterID{ids::secondCore, 1}, "Use a second core",
                                                          false));
    // The string's horizontal polarisation too (docs/design.md section 1): 1 or 2.
    layout.add(choice(ids::polarisations, "Polarisations", juce::StringArray{"1", "2"}, 0));
    // The tanpura's thread across the parabolic bridge (Obstacle.h, layThread).
    const InstrumentStructure s;
    layout.add(std::make_unique<juce::AudioParameterBool>(juce::ParameterID{ids::thread, 1}, "Thread", s.thread));
    layout.add(number(ids::threadPosition, "Thread position", Range(0.0f, 20.0f, 0.01f),
                      float(s.threadOffset / kMetresPerMillimetre), inUnit("mm", 2)));
    layout.add(number(ids::threadDiameter, "Thread diameter", Range(0.05f, 1.0f, 0.01f),
                      float(s.threadDiameter / kMetresPerMillimetre), inUnit("mm", 2)));
    // DAFx-16's damped thread (a spring-damper the string never leaves), or a rigid contact.
    layout.add(choice(ids::threadModel, "Thread model", juce::StringArray{"damped", "rigid"},
                      s.threadModel == ThreadModel::contact ? 1 : 0));
    layout.add(number(ids::threadStiffness, "Thread stiffness", skewed(1.0f, 10000.0f, 120.0f),
                      float(s.threadStiffness / kNewtonsPerKilonewton), inUnit("kN/m", 1)));
    layout.add(number(ids::threadDamping, "Thread damping", skewed(0.0f, 20.0f, 1.2f), float(s.threadDamping),
                      inUnit("kg/s", 2)));
    addBody(layout);
    addSympathetic(layout);
    // How many MIDI strings sound at once (InstrumentControls::midiVoices): fewer costs less.
    layout.add(std::make_unique<juce::AudioParameterInt>(juce::ParameterID{ids::voices, 1}, "Voices", 1, kMidiVoices,
                                                         kControlDefaults.midiVoices));
    return layout;
}

ParameterReader::ParameterReader(juce::AudioProcessorValueTreeState& state)
{
    for (size_t i = 0; i < kParameterCount; ++i)
    {
        values_[i] = state.getRawParameterValue(kParameterIds[i]);
        jassert(values_[i] != nullptr);
    }
}

InstrumentStructure ParameterReader::structure(double hostRateHz) const
{
    constexpr int lastMethod = playerContactMethodCount() - 1;
    InstrumentStructure s;
    s.stringType = rounded(get(ids::stringType));
    s.shape = static_cast<ObstacleShape>(std::clamp(rounded(get(ids::obstacleShape)), 0, 2));
    s.obstaclePosition = get(ids::obstaclePosition);
    s.obstacleWidth = get(ids::obstacleWidth) * kMetresPerMillimetre;
    s.curvature = get(ids::bridgeCurvature);
    s.pluckPosition = get(ids::pluckPosition);
    s.pickupPosition = get(ids::pickupPosition);
    s.inharmonicity = get(ids::inharmonicity);
    s.releaseSeconds = get(ids::release);
    s.quality = rounded(get(ids::quality));
    s.method = kContactMethods[size_t(std::clamp(rounded(get(ids::method)), 0, lastMethod))].method;
    s.polarisations = rounded(get(ids::polarisations)) >= 1 ? 2 : 1;
    s.thread = get(ids::thread) > 0.5f;
    s.threadOffset = get(ids::threadPosition) * kMetresPerMillimetre;
    s.threadDiameter = get(ids::threadDiameter) * kMetresPerMillimetre;
    s.threadModel = rounded(get(ids::threadModel)) == 1 ? ThreadModel::contact : ThreadModel::springDamper;
    s.threadStiffness = get(ids::threadStiffness) * kNewtonsPerKilonewton;
    s.threadDamping = get(ids::threadDamping);
    s.pluck = rounded(get(ids::pluckStyle)) == 1 ? PluckStyle::soft : PluckStyle::sharp;
    s.body = static_cast<BodyChoice>(std::clamp(rounded(get(ids::body)), 0, int(std::size(kBodyNames)) - 1));
    s.bodyTuning = get(ids::bodyTuning);
    s.bodyDamping = get(ids::bodyDamping);
    s.sympatheticStrings = std::clamp(rounded(get(ids::sympathetic)), 0, kMaxSympatheticStrings);
    s.sympatheticJawari = get(ids::sympatheticJawari) > 0.5f;
    s.hostRateHz = hostRateHz;
    return s;
}

InstrumentControls ParameterReader::controls(const std::array<std::atomic<float>, kDampingCurvePoints>& curve) const
{
    InstrumentControls c;
    c.obstacleHeight = get(ids::obstacleHeight) * kMetresPerMillimetre;
    c.stiffness = std::pow(10.0, double(get(ids::obstacleStiffness)));
    c.exponent = get(ids::obstacleExponent);
    c.decayScale = get(ids::decayScale);
    c.airScale = get(ids::airDamping);
    c.deltaVe = get(ids::viscoelasticLoss);
    c.qTeInv = get(ids::thermoelasticLoss) * kThermoelasticUnit;
    for (int i = 0; i < kDampingCurvePoints; ++i)
        c.dampingCurve[size_t(i)] = curve[size_t(i)].load(std::memory_order_relaxed);
    c.gainDb = get(ids::gain);
    c.bodyMix = get(ids::bodyMix);
    c.bendRangeSemitones = get(ids::bendRange);
    c.midiVoices = rounded(get(ids::voices));
    c.drone = get(ids::drone) > 0.5f;
    c.droneTonic = rounded(get(ids::droneTonic));
    c.droneFirst = rounded(get(ids::droneFirst));
    c.droneTempo = get(ids::droneTempo);
    c.humanise = get(ids::humanise);
    c.droneStrength = get(ids::droneStrength);
    c.droneTuning = rounded(get(ids::droneTuning)) == 1 ? DroneTuning::equal : DroneTuning::just;
    c.droneSaHz = get(ids::droneSaHz);
    c.stereoWidth = get(ids::stereoWidth);
    c.droneFineCents = {get(ids::droneFine1), get(ids::droneFine2), get(ids::droneFine3), get(ids::droneFine4)};
    c.sympatheticScale =
        static_cast<SympatheticScale>(std::clamp(rounded(get(ids::sympatheticScale)), 0, kSympatheticScaleCount - 1));
    c.sympatheticIntonation = rounded(get(ids::sympatheticIntonation)) == 1 ? SympatheticIntonation::keyboard
                                                                             : SympatheticIntonation::just;
    c.sympatheticDamping = get(ids::sympatheticDamping);
    c.sympatheticLevel = get(ids::sympatheticLevel);
    return c;
}

MidiSettings ParameterReader::midi() const
{
    return {get(ids::mpe) > 0.5f, get(ids::mpeBendRange)};
}

}  // namespace jawari::plugin
