#include "physics/string/StringDiscretisation.h"

#include <cmath>
#include <numbers>

namespace jawari
{

ModalSolverConfig stringSolverConfig(const StringParameters& string, const std::vector<Obstacle>& obstacles, int modes,
                                     double rateHz, double pickupPosition, PickupQuantity quantity)
{
    const double L = string.lengthMetres;
    const int M = modes;
    ModalSolverConfig c;
    c.lengthMetres = L;
    c.linearDensity = string.linearDensity;
    c.timeStep = 1.0 / rateHz;
    c.modes = buildModalTable(string, M);
    c.contacts = contactPointsOnGrid(obstacles, L, M + 1);
    c.pickupWeights = pickupWeights(string, c.modes, pickupPosition, quantity);
    return c;
}

std::vector<double> pickupWeights(const StringParameters& string, const ModalTable& modes, double position,
                                  PickupQuantity quantity)
{
    const double L = string.lengthMetres;
    const int M = modes.size();
    std::vector<double> h(static_cast<size_t>(M), 0.0);
    for (int p = 1; p <= M; ++p)
    {
        if (quantity == PickupQuantity::force)
        {
            const double k = p * std::numbers::pi / L;
            const double w = modes.omega[size_t(p - 1)];
            h[size_t(p - 1)] = std::sqrt(2.0 / L) * string.linearDensity * w * w / k;
        }
        else
            h[size_t(p - 1)] = modeShape(L, p, position);
    }
    return h;
}

}  // namespace jawari
