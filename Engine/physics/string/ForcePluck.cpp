#include "physics/string/ForcePluck.h"

#include "physics/string/StringModel.h"

#include <cmath>
#include <numbers>

namespace jawari
{

double forcePluckNewtons(const ForcePluck& pluck, double t)
{
    const double s = t - pluck.start;
    if (!(s >= 0.0 && s <= pluck.duration))
        return 0.0;
    const double tau = pluck.duration;
    const double h = 0.5 * (s + tau * std::sinh(pluck.steepness * s / tau) / std::sinh(pluck.steepness));
    const double sine = std::sin(std::numbers::pi * h / tau);
    return pluck.amplitude * sine * sine;
}

std::vector<double> forcePluckModalShape(double lengthMetres, int modeCount, const ForcePluck& pluck)
{
    constexpr double pi = std::numbers::pi;
    std::vector<double> g(static_cast<size_t>(modeCount));
    for (int p = 1; p <= modeCount; ++p)
    {
        const double kw = p * pi / lengthMetres * pluck.width;
        const double denominator = pi * pi - kw * kw;
        // The window's factor, pi/4 at its removable singularity k w = pi.
        const double window = std::abs(denominator) < 1e-9 * pi * pi ? 0.25 * pi
                                                                      : pi * pi * std::cos(0.5 * kw) / denominator;
        g[size_t(p - 1)] = modeShape(lengthMetres, p, pluck.position) * window;
    }
    return g;
}

}  // namespace jawari
