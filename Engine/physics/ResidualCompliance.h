#pragma once
// The dropped modes' static compliance in series with the contact (docs/design.md section 5).
//
// C_ij = sum over the dropped modes of phi_p(x_i) phi_p(x_j) / (mu w_p^2) is the static deflection
// at point i per newton at point j. The dropped modes' quasi-static deflection delta = C W f sits
// in series with the contact: the contact sees u + delta, and delta^{n+1} = C W f^n (backward
// Euler on the massless spring). The contact equation keeps its form with A -> A + C W, and the
// energy H, spring included, can only decrease, by exactly
// (delta^{n+1} - delta^{n-1})^T C^{-1} (delta^{n+1} - delta^{n-1}) / 4 a step.

#include "physics/Obstacle.h"

#include <Eigen/Dense>

#include <vector>

namespace jawari
{

class ResidualCompliance
{
public:
    // OFF: C (P x P, row-major, m/N; empty for none) for the given contact points.
    void prepare(const std::vector<double>& compliance, const std::vector<ContactPoint>& contacts);
    bool active() const { return complianceW_.size() != 0; }
    const Eigen::MatrixXd& complianceW() const { return complianceW_; }  // C W

    // RT: C scaled by `scale` from the configured one (1/r^2 when every frequency is scaled by r).
    void rescale(double scale, const std::vector<ContactPoint>& contacts);
    // RT: delta^{n+1} = C W f = -C W G from the points' slopes G.
    void advance(const double* slope);
    // RT: no deflection at n and n-1.
    void reset();
    double delta(int j) const { return delta_[size_t(j)]; }          // n
    double deltaPrev(int j) const { return deltaPrev_[size_t(j)]; }  // n-1
    // The spring's energy between n-1 and n: (delta^T C^{-1} delta at n and at n-1) / 4. RT (no allocation).
    double energy() const;

private:
    int P_ = 0;
    Eigen::MatrixXd baseC_, baseInverse_;  // as configured (rescale starts from them)
    Eigen::MatrixXd complianceW_, inverse_;
    std::vector<double> delta_, deltaPrev_;
};

}  // namespace jawari
