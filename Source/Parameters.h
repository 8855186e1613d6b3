#pragma once
// The plugin's parameters: ids, ranges and units (README "Parameters"), and how their values become
// the engine's InstrumentStructure (rebuilt off the audio thread) and InstrumentControls (applied
// on the audio thread, smoothed).

#include "realtime/Instrument.h"

#include <juce_audio_processors/juce_audio_processors.h>

#include <array>
#include <atomic>

namespace jawari::plugin
{

namespace ids
{
inline constexpr const char* stringType = "stringType";
inline constexpr const char* obstacleShape = "obstacleShape";
inline constexpr const char* obstaclePosition = "obstaclePosition";
inline constexpr const char* obstacleHeight = "obstacleHeight";
inline constexpr const char* obstacleStiffness = "obstacleStiffness";
inline constexpr const char* obstacleExponent = "obstacleExponent";
inline constexpr const char* obstacleWidth = "obstacleWidth";
inline constexpr const char* bridgeCurvature = "bridgeCurvature";
inline constexpr const char* pluckPosition = "pluckPosition";
inline constexpr const char* pickupPosition = "pickupPosition";
inline constexpr const char* decayScale = "decayScale";
inline constexpr const char* airDamping = "airDamping";
inline constexpr const char* viscoelasticLoss = "viscoelasticLoss";
inline constexpr const char* thermoelasticLoss = "thermoelasticLoss";
inline constexpr const char* inharmonicity = "inharmonicity";
inline constexpr const char* release = "release";
inline constexpr const char* quality = "quality";
inline constexpr const char* method = "method";
inline constexpr const char* gain = "gain";
inline constexpr const char* bendRange = "bendRange";
inline constexpr const char* drone = "drone";
inline constexpr const char* droneTonic = "droneTonic";
inline constexpr const char* droneFirst = "droneFirst";
inline constexpr const char* droneTempo = "droneTempo";
inline constexpr const char* humanise = "humanise";
inline constexpr const char* droneLevel = "droneLevel";
}  // namespace ids

juce::AudioProcessorValueTreeState::ParameterLayout createParameterLayout();

// Raw (denormalised) parameter values, read lock-free from the APVTS atomics.
class ParameterReader
{
public:
    explicit ParameterReader(juce::AudioProcessorValueTreeState& state);

    // CT or RT: the structure for a host rate. No allocation.
    InstrumentStructure structure(double hostRateHz) const;
    // RT: the controls, with the damping curve given.
    InstrumentControls controls(const std::array<std::atomic<float>, kDampingCurvePoints>& curve) const;

private:
    float get(int index) const { return values_[size_t(index)]->load(std::memory_order_relaxed); }
    std::array<std::atomic<float>*, 26> values_{};
};

}  // namespace jawari::plugin
