#include "Parameters.h"

#include <cmath>

namespace jawari::plugin
{
namespace
{
using Range = juce::NormalisableRange<float>;

// The ids in the order ParameterReader indexes them.
constexpr const char* kOrder[] = {ids::stringType,
                                  ids::obstacleShape,
                                  ids::obstaclePosition,
                                  ids::obstacleHeight,
                                  ids::obstacleStiffness,
                                  ids::obstacleExponent,
                                  ids::obstacleWidth,
                                  ids::bridgeCurvature,
                                  ids::pluckPosition,
                                  ids::pickupPosition,
                                  ids::decayScale,
                                  ids::airDamping,
                                  ids::viscoelasticLoss,
                                  ids::thermoelasticLoss,
                                  ids::inharmonicity,
                                  ids::release,
                                  ids::quality,
                                  ids::method,
                                  ids::gain,
                                  ids::bendRange,
                                  ids::drone,
                                  ids::droneTonic,
                                  ids::droneFirst,
                                  ids::droneTempo,
                                  ids::humanise,
                                  ids::droneLevel};
static_assert(std::size(kOrder) == 26);

Range skewed(float lo, float hi, float centre)
{
    Range r(lo, hi);
    r.setSkewForCentre(centre);
    return r;
}

std::unique_ptr<juce::AudioParameterFloat> number(const char* id, const char* name, Range range, float value,
                                                  const char* unit, int decimals = 3)
{
    return std::make_unique<juce::AudioParameterFloat>(
        juce::ParameterID{id, 1}, name, range, value,
        juce::AudioParameterFloatAttributes().withLabel(unit).withStringFromValueFunction([decimals](float v, int) {
            // No "-0.0000" for a value that rounds to zero.
            return juce::String(std::abs(v) < 0.5f * std::pow(10.0f, float(-decimals)) ? 0.0f : v, decimals);
        }));
}
}  // namespace

juce::AudioProcessorValueTreeState::ParameterLayout createParameterLayout()
{
    juce::AudioProcessorValueTreeState::ParameterLayout layout;
    juce::StringArray strings;
    for (const auto& s : kStringTypes)
        strings.add(s.name);
    layout.add(
        std::make_unique<juce::AudioParameterChoice>(juce::ParameterID{ids::stringType, 1}, "String", strings, 0));
    layout.add(std::make_unique<juce::AudioParameterChoice>(juce::ParameterID{ids::obstacleShape, 1}, "Obstacle shape",
                                                            juce::StringArray{"point", "parabolic bridge", "frets"},
                                                            0));
    layout.add(number(ids::obstaclePosition, "Obstacle position", Range(0.005f, 0.995f), 0.006f, "x L", 4));
    layout.add(number(ids::obstacleHeight, "Obstacle height", Range(-5.0f, 1.0f, 0.0001f), 0.0f, "mm", 4));
    layout.add(number(ids::obstacleStiffness, "Obstacle stiffness", Range(6.0f, 16.0f, 0.01f), 13.0f, "log10 K", 2));
    layout.add(number(ids::obstacleExponent, "Obstacle exponent", Range(1.0f, 4.0f, 0.01f), 1.3f, "alpha", 2));
    layout.add(number(ids::obstacleWidth, "Obstacle width", skewed(0.1f, 50.0f, 3.0f), 1.0f, "mm", 2));
    layout.add(number(ids::bridgeCurvature, "Bridge curvature", skewed(0.0f, 100.0f, 5.0f), 2.0f, "1/m", 2));
    layout.add(number(ids::pluckPosition, "Pluck position", Range(0.02f, 0.98f), 0.5f, "x L", 4));
    layout.add(number(ids::pickupPosition, "Pickup position", Range(0.01f, 0.995f), 0.992f / 1.002f, "x L", 4));
    layout.add(number(ids::decayScale, "Decay scale", skewed(0.1f, 10.0f, 1.0f), 1.0f, "x", 2));
    layout.add(number(ids::airDamping, "Air damping", skewed(0.0f, 10.0f, 1.0f), 1.0f, "x", 2));
    layout.add(number(ids::viscoelasticLoss, "Viscoelastic loss", Range(0.0f, 0.05f, 0.0001f), 0.006f, "delta_ve", 4));
    layout.add(number(ids::thermoelasticLoss, "Thermoelastic loss", Range(0.0f, 10.0f, 0.01f), 1.38f, "1e-4/Q", 2));
    layout.add(number(ids::inharmonicity, "Inharmonicity", skewed(0.0f, 1e-3f, 5e-5f), 1.78e-5f, "B", 7));
    layout.add(number(ids::release, "Release", skewed(0.05f, 5.0f, 0.5f), 0.4f, "s", 2));
    layout.add(std::make_unique<juce::AudioParameterChoice>(
        juce::ParameterID{ids::quality, 1}, "Quality", juce::StringArray{"draft", "standard", "high", "paper"}, 0));
    layout.add(std::make_unique<juce::AudioParameterChoice>(
        juce::ParameterID{ids::method, 1}, "Contact method",
        juce::StringArray{"energy-conserving", "quadratised", "penalty"}, 0));
    layout.add(number(ids::gain, "Output gain", Range(-48.0f, 12.0f, 0.1f), 0.0f, "dB", 1));
    layout.add(number(ids::bendRange, "Pitch bend range", Range(0.0f, 12.0f, 1.0f), 2.0f, "semitones", 0));
    layout.add(std::make_unique<juce::AudioParameterBool>(juce::ParameterID{ids::drone, 1}, "Drone", false));
    layout.add(std::make_unique<juce::AudioParameterInt>(juce::ParameterID{ids::droneTonic, 1}, "Drone tonic (Sa)", 36,
                                                         72, 49));
    layout.add(std::make_unique<juce::AudioParameterChoice>(juce::ParameterID{ids::droneFirst, 1}, "First string",
                                                            juce::StringArray{"Pa", "Ma", "Ni", "Sa"}, 0));
    layout.add(number(ids::droneTempo, "Drone tempo", Range(20.0f, 200.0f, 0.1f), 60.0f, "plucks/min", 1));
    layout.add(number(ids::humanise, "Humanise", Range(0.0f, 1.0f, 0.001f), 0.2f, "", 2));
    layout.add(number(ids::droneLevel, "Drone strength", Range(0.0f, 1.0f, 0.001f), 0.7f, "", 2));
    return layout;
}

ParameterReader::ParameterReader(juce::AudioProcessorValueTreeState& state)
{
    for (size_t i = 0; i < std::size(kOrder); ++i)
    {
        values_[i] = state.getRawParameterValue(kOrder[i]);
        jassert(values_[i] != nullptr);
    }
}

InstrumentStructure ParameterReader::structure(double hostRateHz) const
{
    InstrumentStructure s;
    s.stringType = static_cast<int>(std::lround(get(0)));
    s.shape = static_cast<ObstacleShape>(std::clamp(static_cast<int>(std::lround(get(1))), 0, 2));
    s.obstaclePosition = get(2);
    s.obstacleWidth = get(6) * 1e-3;
    s.curvature = get(7);
    s.pluckPosition = get(8);
    s.pickupPosition = get(9);
    s.inharmonicity = get(14);
    s.releaseSeconds = get(15);
    s.quality = static_cast<int>(std::lround(get(16)));
    s.method = static_cast<ContactMethod>(std::clamp(static_cast<int>(std::lround(get(17))), 0, 2));
    s.hostRateHz = hostRateHz;
    return s;
}

InstrumentControls ParameterReader::controls(const std::array<std::atomic<float>, kDampingCurvePoints>& curve) const
{
    InstrumentControls c;
    c.obstacleHeight = get(3) * 1e-3;
    c.stiffness = std::pow(10.0, double(get(4)));
    c.exponent = get(5);
    c.decayScale = get(10);
    c.airScale = get(11);
    c.deltaVe = get(12);
    c.qTeInv = get(13) * 1e-4;
    for (int i = 0; i < kDampingCurvePoints; ++i)
        c.dampingCurve[size_t(i)] = curve[size_t(i)].load(std::memory_order_relaxed);
    c.gainDb = get(18);
    c.bendRangeSemitones = get(19);
    c.drone = get(20) > 0.5f;
    c.droneTonic = static_cast<int>(std::lround(get(21)));
    c.droneFirst = static_cast<int>(std::lround(get(22)));
    c.droneTempo = get(23);
    c.humanise = get(24);
    c.droneStrength = get(25);
    return c;
}

}  // namespace jawari::plugin
