#include "Quality.h"

#include <algorithm>
#include <cmath>

namespace jawari
{

std::optional<QualitySetting> qualityByName(const std::string& name)
{
    for (const auto& q : kQualitySettings)
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
    return q;
}

double reachAt(const Scene& scene, double x)
{
    const double L = scene.string.lengthMetres;
    const double xe = scene.excitation.position;
    if (!(x > 0.0 && x < L) || !(xe > 0.0 && xe < L))
        return 0.0;
    return 1.25 * std::abs(scene.excitation.amplitude) * std::sqrt(x * (L - x) / (xe * (L - xe)));
}

bool obstacleReachable(const Scene& scene, const Obstacle& obstacle)
{
    if (scene.simulation.method != Method::realtime && scene.simulation.method != Method::reference)
        return true;
    if (!obstacle.isDistributed())
        return obstacle.height + reachAt(scene, obstacle.position) > 0.0;
    // Finer than any grid the voice samples it on (M + 1 <= a few thousand intervals).
    const double a = std::max(obstacle.supportBegin(), 0.0),
                 b = std::min(obstacle.supportEnd(), scene.string.lengthMetres);
    constexpr int kSamples = 4096;
    for (int i = 0; i <= kSamples; ++i)
    {
        const double x = a + (b - a) * i / kSamples;
        if (obstacle.heightAt(x) + reachAt(scene, x) > 0.0)
            return true;
    }
    return false;
}

VoiceQuality automaticQuality(const Scene& scene)
{
    const double host = scene.simulation.outputRateHz;
    VoiceQuality q;
    bool reachable = false;
    for (const auto& o : scene.obstacles)
        reachable = reachable || obstacleReachable(scene, o);
    if (!reachable)
    {
        // No contact: every mode is exact at any rate (DESIGN.md section 2), so the host rate
        // itself, and only the modes below the audio band (or the host's Nyquist frequency).
        q = resolveQuality({"free", std::min(20000.0, 0.45 * host), host}, scene.string, host);
    }
    else
        q = resolveQuality(*qualityByName("standard"), scene.string, host);
    if (scene.simulation.modes)
        q.modes = *scene.simulation.modes;
    if (scene.simulation.rateHz)
        q.oversampling = static_cast<int>(std::lround(*scene.simulation.rateHz / host));
    return q;
}

}  // namespace jawari
