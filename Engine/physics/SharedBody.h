#pragma once
// Strings that stand on one body, each in its own solver, stepped together: the partitioned form of
// the one solver that appendString and withBody build (ModalBody.h; docs/design.md section 1,
// "Strings that share the body"), for strings that must keep their own solvers (the instrument's).
//
// Each string has one energy-conserving contact point on the body (its solver's point 0, weight w_i).
// In the joined solver the points' equations are r_i + A_ii G_i(r_i) + beta sum_j w_j G_j(r_j) = b_i,
// with beta = dt^2 kappa^2 sum_k 1/m_k: the body couples every pair of points by rank one, and the
// points see the string's displacement less the bridge's, w = kappa sum_k z_k. So a step is: each
// string predicts (ModalSolver::beginStep) and the body predicts; each string's s and b are shifted
// by the bridge's w^{n-1} and its predicted move; the coupled equations are solved together
// (ContactSystem); each string finishes with its r and slope, and the body takes the force
// F = sum_i w_i G_i on its modes, z^{n+1} = a z^n - e z^{n-1} + (dt^2 kappa / m_k) F. The same
// equations as the joined solver's, so the same energy balance, to rounding.

#include "physics/ContactSystem.h"
#include "physics/ExactOscillator.h"
#include "physics/ModalBody.h"
#include "physics/ModalSolver.h"

#include <vector>

namespace jawari
{

class SharedBody
{
public:
    // OFF: the body under `strings` (each with exactly one contact point, energy-conserving), at rest,
    // coupled by `coupling`, at the strings' common time step.
    SharedBody(const ModalBody& body, double coupling, const std::vector<ModalSolver*>& strings);

    // RT: one step of the strings given at construction, in that order, and of the body. False, and
    // nothing stepped, when a string's next step would not wait for its point's solution
    // (ModalSolver::nextStepWaits: an explicit force on it).
    bool step(ModalSolver* const* strings, int count);

    double bridgeDisplacement() const;  // RT: w^n (m)
    double lastBridgeForce() const { return force_; }  // RT: F of the last step (N, pushing the body down)

private:
    std::vector<ExactModeCoefficients> coefficients_;
    std::vector<double> push_;  // dt^2 kappa / m_k
    std::vector<double> z_, zPrevious_, zNext_;
    double coupling_ = 1.0, dt_ = 0.0, force_ = 0.0;
    ContactSystem system_;
    std::vector<ScalarContactRequest> requests_;
    std::vector<double> weight_, s_, b_, r_, slope_;
};

}  // namespace jawari
