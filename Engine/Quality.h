#pragma once
// How much model a voice runs: M modes and the oversampling R / host rate (DESIGN.md section 5).
// Named settings and the automatic choice from a scene. OFF.

#include "Scene.h"

#include <optional>
#include <string>

namespace jawari
{

struct VoiceQuality
{
    int modes = 0;
    int oversampling = 1;
};

struct QualitySetting
{
    const char* name;
    double highestModeHz;  // keep the modes up to this frequency
    double minimumRateHz;  // and run at least this fast (a whole multiple of the host rate)
};

// From cheap to the paper's configuration in real time.
inline constexpr QualitySetting kQualitySettings[] = {
    {"draft", 24000.0, 192000.0},
    {"standard", 48000.0, 384000.0},
    {"high", 96000.0, 768000.0},
    {"paper", 0.0, 1000000.0},  // every mode of the paper's grid (1001 for its string), >= 1 MHz
};

std::optional<QualitySetting> qualityByName(const std::string& name);

// M and the oversampling a setting gives for a string at a host rate.
VoiceQuality resolveQuality(const QualitySetting& setting, const StringParameters& string, double hostRateHz);

// The automatic choice: the scene's own modes/rate where given; else, with no obstacle, the modes
// below 20 kHz at the host rate (no contact, nothing to oversample), and the standard setting
// otherwise.
VoiceQuality automaticQuality(const Scene& scene);

}  // namespace jawari
