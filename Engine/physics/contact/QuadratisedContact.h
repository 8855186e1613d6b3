#pragma once
// The energy-quadratised contact (scalar auxiliary variable; Ducceschi & Bilbao 2019; docs/design.md
// section 4): no Newton, one rank-one solve a step, and a quadratised energy conserved exactly. A
// bilateral law (ContactLaw.h) joins V with its spring and drops its damper.
//
// V(u) = sum_j w_j psi_j(u_j) = xi^2 / 2 with xi carried as a state. With g = dV/du / sqrt(2 V)
// at u^n, the point forces are F = -g (xi^{n+1} + xi^{n-1}) / 2 and xi^{n+1} = xi^{n-1} + g . R,
// where R = b + B F is the points' displacement change (B = A' W^{-1}, A' the coupling with any
// residual compliance). So (I + B g g^T / 2) R = b - B g xi^{n-1}: Sherman-Morrison, no iteration.

#include "physics/contact/Obstacle.h"

#include <Eigen/Dense>

#include <vector>

namespace jawari
{

class QuadratisedContact
{
public:
    void prepare(int points);  // OFF: sizes the workspace
    // RT: xi = sqrt(2 V) at n and n-1 from the points' displacements u (penetration g - u).
    void restart(const std::vector<ContactPoint>& contacts, const double* u, const double* uPrev);
    void reset();  // RT: xi = 0 (the string at rest)
    // RT: the slopes G_j of the step from the penetrations at n and b (the contact-free change of
    // each point), with B = `pointCoupling`. Returns 0 iterations.
    int solve(const std::vector<ContactPoint>& contacts, const double* penetration, const double* b,
              const Eigen::MatrixXd& pointCoupling, double* slope);
    // The quadratised contact energy between n-1 and n: (xi_n^2 + xi_{n-1}^2) / 4.
    double energy() const { return 0.25 * (xi_ * xi_ + xiPrev_ * xiPrev_); }

private:
    std::vector<double> gradient_, response_;  // g and B g
    double xi_ = 0.0, xiPrev_ = 0.0;
};

}  // namespace jawari
