#pragma once
// The string's linear modes with its bilateral points' springs folded in (the damped thread holds
// the string at rest, so it moves the pitch as a finger's stop would): the note tuned is the mode
// the string sounds with its thread, not without.

#include "physics/modes/ModalSolver.h"

namespace jawari
{

// The frequency (Hz) of the linear mode that grows from the solver's mode k when the springs of its
// bilateral contact points are added: the eigenvalue of Omega^2 + sum_j (w_j K_j / mu) s_j s_j^T
// (s_j point j's row over the modes; the springs in series with the solver's residual compliance
// there, as its contact solve meets them) that Rayleigh quotient iteration reaches from e_k, each
// (A - sigma I)^{-1} through the Woodbury identity in O(N P) for P bilateral points. Mode k's own
// frequency when no point is bilateral. OFF.
double springLoadedFrequencyHz(const ModalSolverConfig& config, int k);

}  // namespace jawari
