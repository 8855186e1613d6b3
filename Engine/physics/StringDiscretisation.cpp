#include "physics/StringDiscretisation.h"

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
    c.pickupWeights.resize(M);
    for (int p = 1; p <= M; ++p)
    {
        if (quantity == PickupQuantity::force)
        {
            const double k = p * std::numbers::pi / L;
            const double w = c.modes.omega[p - 1];
            c.pickupWeights[p - 1] = std::sqrt(2.0 / L) * string.linearDensity * w * w / k;
        }
        else
            c.pickupWeights[p - 1] = modeShape(L, p, pickupPosition);
    }
    return c;
}

}  // namespace jawari
