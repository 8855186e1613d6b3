#pragma once
// The plugin's parameters: ids, ranges and units (README "Parameters"), and how their values become
// the engine's InstrumentStructure (rebuilt off the audio thread) and InstrumentControls (applied
// on the audio thread, smoothed).

#include "realtime/instrument/InstrumentSettings.h"

#include <juce_audio_processors/juce_audio_processors.h>

#include <array>
#include <atomic>
#include <cstddef>
#include <iterator>
#include <string_view>

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
inline constexpr const char* droneStrength = "droneStrength";
inline constexpr const char* droneTuning = "droneTuning";
inline constexpr const char* droneSaHz = "droneSaHz";
inline constexpr const char* droneFine1 = "droneFine1";
inline constexpr const char* droneFine2 = "droneFine2";
inline constexpr const char* droneFine3 = "droneFine3";
inline constexpr const char* droneFine4 = "droneFine4";
inline constexpr const char* mpe = "mpe";
inline constexpr const char* stereoWidth = "stereoWidth";
inline constexpr const char* mpeBendRange = "mpeBendRange";
inline constexpr const char* secondCore = "secondCore";
inline constexpr const char* polarisations = "polarisations";
inline constexpr const char* thread = "thread";
inline constexpr const char* threadPosition = "threadPosition";
inline constexpr const char* threadDiameter = "threadDiameter";
inline constexpr const char* threadModel = "threadModel";
inline constexpr const char* threadStiffness = "threadStiffness";
inline constexpr const char* threadDamping = "threadDamping";
inline constexpr const char* pluckStyle = "pluckStyle";
inline constexpr const char* body = "body";
inline constexpr const char* bodyMix = "bodyMix";
inline constexpr const char* bodyTuning = "bodyTuning";
inline constexpr const char* bodyDamping = "bodyDamping";
inline constexpr const char* sympathetic = "sympathetic";
inline constexpr const char* sympatheticScale = "sympatheticScale";
inline constexpr const char* sympatheticIntonation = "sympatheticIntonation";
inline constexpr const char* sympatheticDamping = "sympatheticDamping";
inline constexpr const char* sympatheticLevel = "sympatheticLevel";
inline constexpr const char* sympatheticJawari = "sympatheticJawari";
inline constexpr const char* voices = "voices";
}  // namespace ids

// Every parameter, in the order the host lists them (createParameterLayout adds them in this order).
inline constexpr const char* kParameterIds[] = {ids::stringType,
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
                                                ids::droneStrength,
                                                ids::droneTuning,
                                                ids::droneSaHz,
                                                ids::droneFine1,
                                                ids::droneFine2,
                                                ids::droneFine3,
                                                ids::droneFine4,
                                                ids::mpe,
                                                ids::mpeBendRange,
                                                ids::stereoWidth,
                                                ids::secondCore,
                                                ids::polarisations,
                                                ids::thread,
                                                ids::threadPosition,
                                                ids::threadDiameter,
                                                ids::threadModel,
                                                ids::threadStiffness,
                                                ids::threadDamping,
                                                ids::pluckStyle,
                                                ids::body,
                                                ids::bodyMix,
                                                ids::bodyTuning,
                                                ids::bodyDamping,
                                                ids::sympathetic,
                                                ids::sympatheticScale,
                                                ids::sympatheticIntonation,
                                                ids::sympatheticDamping,
                                                ids::sympatheticLevel,
                                                ids::sympatheticJawari,
                                                ids::voices};
inline constexpr std::size_t kParameterCount = std::size(kParameterIds);

// Ids that saved states and user presets may still use for a parameter: read into `id`.
struct ParameterAlias
{
    const char* oldId;
    const char* id;
};
inline constexpr ParameterAlias kParameterAliases[] = {{"droneLevel", ids::droneStrength}};

// A parameter's position in kParameterIds, found while compiling: an id not in the list does not
// compile, and reading a parameter costs no string comparison at run time.
class ParameterIndex
{
public:
    consteval ParameterIndex(const char* id)
        : index_(find(id))
    {}
    constexpr std::size_t value() const { return index_; }

private:
    static consteval std::size_t find(std::string_view id)
    {
        for (std::size_t i = 0; i < kParameterCount; ++i)
            if (id == kParameterIds[i])
                return i;
        throw "not a parameter id (kParameterIds)";
    }
    std::size_t index_;
};

juce::AudioProcessorValueTreeState::ParameterLayout createParameterLayout();

// Raw (denormalised) parameter values, read lock-free from the APVTS atomics. The atomics are
// found by id once, at construction (CT); reading them does no lookup.
// How the plugin reads MIDI: MPE (per-note expression, the lower zone: channel 1 the master,
// 2..16 one note each) or not.
struct MidiSettings
{
    bool mpe = false;
    double mpeBendRange = 48.0;  // semitones of a member channel's full bend (the MPE default)
};

class ParameterReader
{
public:
    explicit ParameterReader(juce::AudioProcessorValueTreeState& state);

    // CT or RT: the structure for a host rate. No allocation.
    InstrumentStructure structure(double hostRateHz) const;
    // RT: the controls, with the damping curve given.
    InstrumentControls controls(const std::array<std::atomic<float>, kDampingCurvePoints>& curve) const;
    MidiSettings midi() const;  // RT
    bool secondCore() const { return get(ids::secondCore) > 0.5f; }  // RT: "use a second core"

private:
    float get(ParameterIndex id) const { return values_[id.value()]->load(std::memory_order_relaxed); }
    std::array<std::atomic<float>*, kParameterCount> values_{};
};

}  // namespace jawari::plugin
