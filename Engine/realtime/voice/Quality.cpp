#include "realtime/voice/Quality.h"

#include <algorithm>
#include <cmath>

namespace jawari
{

std::span<const QualitySetting> qualitySettings(ObstacleKind kind)
{
    if (kind == ObstacleKind::bridge)
        return kBridgeQualitySettings;
    return kQualitySettings;
}

std::optional<QualitySetting> qualityByName(const std::string& name, ObstacleKind kind)
{
    for (const auto& q : qualitySettings(kind))
        if (name == q.name)
            return q;
    return std::nullopt;
}

VoiceQuality resolveQuality(const QualitySetting& setting, const StringParameters& string, double hostRateHz)
{
    VoiceQuality q;
    if (setting.highestModeHz <= 0.0)
        q.modes = kReferenceModes;
    else
    {
        const double f0 = string.flexibleFundamentalHz();
        const double B = string.inharmonicity;
        int M = 1;
        while (M < kMaxModes && (M + 1) * f0 * std::sqrt(1.0 + B * (M + 1.0) * (M + 1.0)) <= setting.highestModeHz)
            ++M;
        q.modes = M;
    }
    q.oversampling = std::clamp(static_cast<int>(std::ceil(setting.minimumRateHz / hostRateHz - 1e-9)), 1, 256);
    q.contactIntervals = setting.contactIntervals;
    return q;
}

}  // namespace jawari
