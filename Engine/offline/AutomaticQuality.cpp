#include "offline/AutomaticQuality.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace jawari
{

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
    if (!scene.simulation.reference && scene.simulation.contact != ContactMethod::energyConserving)
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

double contactTimeConstant(const Scene& scene, const Obstacle& obstacle)
{
    const auto& str = scene.string;
    const double L = str.lengthMetres;
    const double impedance = 2.0 * std::sqrt(str.tensionNewtons * str.linearDensity);
    const double c = std::sqrt(str.tensionNewtons / str.linearDensity);
    const double xe = std::clamp(scene.excitation.position, 1e-9 * L, L * (1.0 - 1e-9));
    const double v = c * std::abs(scene.excitation.amplitude) / std::min(xe, L - xe);
    // The width that presses: a point's weight, or a distributed obstacle's whole extent (the most
    // it could press with, hence the stiffest and shortest).
    const double w = obstacle.isDistributed() ? obstacle.supportEnd() - obstacle.supportBegin() : obstacle.width;
    const double K = obstacle.law.stiffness, alpha = obstacle.law.exponent;
    if (!(w > 0.0 && K > 0.0 && v > 0.0))
        return std::numeric_limits<double>::infinity();
    const double depth = std::pow(impedance * v / (w * K), 1.0 / alpha);
    const double stiffness = w * K * alpha * std::pow(depth, alpha - 1.0);  // N/m at that depth
    return impedance / stiffness;
}

VoiceQuality automaticQuality(const Scene& scene)
{
    const double host = scene.simulation.outputRateHz;
    VoiceQuality q;
    bool reachable = false, bridge = false;
    for (const auto& o : scene.obstacles)
    {
        const bool touches = obstacleReachable(scene, o);
        reachable = reachable || touches;
        bridge = bridge || (touches && o.isDistributed());
    }
    if (!reachable)
    {
        // No contact: every mode is exact at any rate (docs/design.md section 2), so the host rate
        // itself, and only the modes below the audio band (or the host's Nyquist frequency).
        q = resolveQuality({"free", std::min(20000.0, 0.45 * host), host}, scene.string, host);
    }
    else
    {
        q = resolveQuality(*qualityByName("standard", bridge ? ObstacleKind::bridge : ObstacleKind::points),
                           scene.string, host);
        // A soft contact lasts long enough to be followed at a lower rate: 16 steps per contact
        // time constant, and at least 2.5 x the highest kept mode so the modes are not aliased.
        double shortest = std::numeric_limits<double>::infinity();
        for (const auto& o : scene.obstacles)
            if (obstacleReachable(scene, o))
                shortest = std::min(shortest, contactTimeConstant(scene, o));
        const double fM = scene.string.flexibleFundamentalHz() * q.modes
                          * std::sqrt(1.0 + scene.string.inharmonicity * q.modes * q.modes);
        const double needed = std::max({16.0 / shortest, 2.5 * fM, 2.0 * host});
        if (needed < q.oversampling * host)
            q.oversampling = std::max(2, static_cast<int>(std::ceil(needed / host - 1e-9)));
    }
    if (scene.simulation.modes)
        q.modes = *scene.simulation.modes;
    if (scene.simulation.rateHz)
        q.oversampling = static_cast<int>(std::lround(*scene.simulation.rateHz / host));
    return q;
}

}  // namespace jawari
