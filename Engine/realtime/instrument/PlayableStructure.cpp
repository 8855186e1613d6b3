#include "realtime/instrument/PlayableStructure.h"

#include "realtime/voice/Quality.h"

#include <algorithm>
#include <cmath>
#include <iterator>

namespace jawari
{
namespace
{
// v clamped to [lowest, highest], or `fallback` when v is not a number.
double within(double v, double lowest, double highest, double fallback)
{
    return std::isnan(v) ? fallback : std::clamp(v, lowest, highest);
}

bool knownMethod(ContactMethod m)
{
    switch (m)
    {
        case ContactMethod::energyConserving:
        case ContactMethod::quadratised:
        case ContactMethod::penalty:
        case ContactMethod::quadraticSpline: return true;
    }
    return false;
}

bool knownShape(ObstacleShape shape)
{
    return shape == ObstacleShape::point || shape == ObstacleShape::parabola || shape == ObstacleShape::frets;
}

// A parabolic bridge's apex moved so that its whole width lies on the string [0, L]; a bridge
// within a micrometre of an end is left as it is (a preset's bridge that reaches the nut exactly).
double bridgeOnString(double fraction, double width, double L)
{
    constexpr double slack = 1e-6;  // m
    const double apex = fraction * L, half = 0.5 * width;
    if (apex - half < -slack)
        return half / L;
    if (apex + half > L + slack)
        return (L - half) / L;
    return fraction;
}
}  // namespace

bool playableHostRate(double hostRateHz)
{
    return hostRateHz >= 8000.0 && hostRateHz <= 384000.0;
}

InstrumentStructure playableStructure(const InstrumentStructure& s)
{
    static constexpr InstrumentStructure d{};
    InstrumentStructure p = s;
    p.stringType = std::clamp(s.stringType, 0, kStringTypeCount - 1);
    p.shape = knownShape(s.shape) ? s.shape : d.shape;
    p.method = knownMethod(s.method) ? s.method : d.method;
    p.quality = std::clamp(s.quality, 0, static_cast<int>(std::size(kQualitySettings)) - 1);
    p.polarisations = s.polarisations >= 2 ? 2 : 1;
    p.obstaclePosition = within(s.obstaclePosition, 0.005, 0.995, d.obstaclePosition);
    p.pluckPosition = within(s.pluckPosition, 0.005, 0.995, d.pluckPosition);
    p.pickupPosition = within(s.pickupPosition, 0.005, 0.995, d.pickupPosition);
    p.curvature = within(s.curvature, 0.0, 1e4, d.curvature);
    p.inharmonicity = within(s.inharmonicity, 0.0, 1e-2, d.inharmonicity);
    p.releaseSeconds = within(s.releaseSeconds, 0.01, 60.0, d.releaseSeconds);
    p.threadDiameter = within(s.threadDiameter, 1e-6, 5e-3, d.threadDiameter);
    p.threadModel = s.threadModel == ThreadModel::contact ? ThreadModel::contact : ThreadModel::springDamper;
    p.threadStiffness = within(s.threadStiffness, 1e2, 1e8, d.threadStiffness);
    p.threadDamping = within(s.threadDamping, 0.0, 100.0, d.threadDamping);
    const double L = kStringTypes[p.stringType].lengthMetres;
    // At most 5 cm (the plugin's range): a bridge's contact points, one per 0.9 mm, are solved
    // together at every step, and a wider one could not be in real time.
    p.obstacleWidth = within(s.obstacleWidth, 1e-5, kWidestObstacleMetres, d.obstacleWidth);
    p.threadOffset = std::min(within(s.threadOffset, 0.0, p.obstacleWidth, d.threadOffset), p.obstacleWidth);
    if (p.shape == ObstacleShape::parabola)
        p.obstaclePosition = bridgeOnString(p.obstaclePosition, p.obstacleWidth, L);
    return p;
}

}  // namespace jawari
