#pragma once
// How much model a voice runs: M modes and the oversampling R / host rate (docs/design.md
// section 5), and the named settings a player chooses from. (The automatic choice for a scene is
// offline/AutomaticQuality.h.) OFF.

#include "physics/string/StringModel.h"

#include <optional>
#include <span>
#include <string>

namespace jawari
{

struct VoiceQuality
{
    int modes = 0;
    int oversampling = 1;
    int contactIntervals = 0;  // a bridge's points L / this apart; 0: its own grid (Obstacle.h)
};

struct QualitySetting
{
    const char* name;
    double highestModeHz;      // keep the modes up to this frequency
    double minimumRateHz;      // and run at least this fast (a whole multiple of the host rate)
    int contactIntervals = 0;  // a bridge's contact points L / this apart; 0: its own grid
};

// From cheap to the paper's configuration in real time.
inline constexpr QualitySetting kQualitySettings[] = {
    {"draft", 24000.0, 192000.0},
    {"standard", 51300.0, 288000.0},  // from the measured front (docs/measurements.md): M = 200 for the paper's string
    {"high", 96000.0, 768000.0},
    {"paper", 0.0, 1000000.0},  // every mode of the paper's grid (1001 for its string), >= 1 MHz
};

// A bridge (a distributed obstacle) touches over a stretch of contact points, so each step solves
// them together. On its own points 0.9 mm apart a voice comes no nearer its converged reference than
// about 2.3 dB at any modes or rate (sitar-bridge: 2.35 dB at 142 modes and 144 kHz; docs/
// measurements.md), so the standard runs at a third of the point table's rate with the modes to
// 34.5 kHz. High takes the point table's modes on points four times finer (L/4008, 0.22 mm on the
// Sitar's string) at 288 kHz: 1.28 dB from it, where the point table's high on the bridge's own
// points is 2.26 dB for about the same CPU. Same names in the same order; "paper" is the point table's.
inline constexpr QualitySetting kBridgeQualitySettings[] = {
    {"draft", 24000.0, 96000.0},
    {"standard", 34500.0, 144000.0},
    {"high", 96000.0, 288000.0, 4008},
    {"paper", 0.0, 1000000.0},
};
static_assert(std::size(kBridgeQualitySettings) == std::size(kQualitySettings));

// The table for a string on these obstacles: kBridgeQualitySettings when one is distributed.
enum class ObstacleKind
{
    points,
    bridge
};
std::span<const QualitySetting> qualitySettings(ObstacleKind kind);

std::optional<QualitySetting> qualityByName(const std::string& name, ObstacleKind kind = ObstacleKind::points);

// M and the oversampling a setting gives for a string at a host rate.
VoiceQuality resolveQuality(const QualitySetting& setting, const StringParameters& string, double hostRateHz);

}  // namespace jawari
