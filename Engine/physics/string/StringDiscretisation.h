#pragma once
// What the reference and the voice share: the string cut to M modes at a rate R, its obstacles
// turned into contact points, and the pickup as weights on the modes. OFF.

#include "physics/modes/ModalSolver.h"
#include "physics/contact/Obstacle.h"
#include "physics/modes/Pickup.h"
#include "physics/string/StringModel.h"

#include <vector>

namespace jawari
{

// M modes of the string at rate R, the contact points (point obstacles at their positions,
// distributed ones sampled on the grid x_i = i L/(M+1), the reference grid when M = N - 1) and the
// pickup weights (phi_p at the pickup for displacement and velocity; phi_p'(0) mu w_p^2 / k_p^2 for
// the force on the termination at x = 0, which is T u_x(0) - EI u_xxx(0) for the law and keeps
// the modal stiffness for measured frequencies).
ModalSolverConfig stringSolverConfig(const StringParameters& string, const std::vector<Obstacle>& obstacles, int modes,
                                     double rateHz, double pickupPosition, PickupQuantity quantity);

// The pickup weights of the string's modes (as stringSolverConfig gives them) for a pickup at
// `position` (m) reading `quantity`.
std::vector<double> pickupWeights(const StringParameters& string, const ModalTable& modes, double position,
                                  PickupQuantity quantity);

}  // namespace jawari
