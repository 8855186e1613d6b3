#pragma once
// The dropped modes' static compliance in series with the contact (docs/design.md section 5).
//
// C_ij = sum over the dropped modes of phi_p(x_i) phi_p(x_j) / (mu w_p^2) is the static deflection
// at point i per newton at point j. The dropped modes' deflection delta = C g sits in series with
// the contact: the contact sees u + delta, and the spring's force g answers the contact's force
// F = W f by the theta-average
//
//   ((1 + theta) g^{n+1} + (1 - theta) g^{n-1}) / 2 = F^n,   delta = C g,
//
// so that delta^{n+1} = kappa C F^n - (kappa - 1) delta^{n-1} with kappa = 2 / (1 + theta), and the
// contact equation keeps its form with A -> A + kappa C W and b -> b - kappa delta^{n-1}. The
// spring stores (g^{n+1} C g^{n+1} + g^n C g^n) / 4 = (g^{n+1} . delta^{n+1} + g^n . delta^n) / 4
// (no inverse of C: coincident points, whose C is singular, are no exception), and the work F^n .
// (delta^{n+1} - delta^{n-1}) / 2 changes that by exactly its rise plus the loss
// theta (g^{n+1} - g^{n-1}) C (g^{n+1} - g^{n-1}) / 4 >= 0. theta = 0 (the trapezoid) conserves;
// theta = 1 is backward Euler on the massless spring, delta^{n+1} = C F^n.

#include "physics/contact/Obstacle.h"

#include <Eigen/Dense>

#include <vector>

namespace jawari
{

class ResidualCompliance
{
public:
    // OFF: C (P x P, row-major, m/N; empty for none) for the given contact points, and theta in
    // [0, 1], the share of the spring's two-step change that it dissipates.
    void prepare(const std::vector<double>& compliance, const std::vector<ContactPoint>& contacts, double theta);
    bool active() const { return coupling_.size() != 0; }
    // What the spring adds to the contact equation's coupling A: kappa C W.
    const Eigen::MatrixXd& coupling() const { return coupling_; }
    double diagonal(int j) const { return coupling_(j, j) / kappa_ / weights_[size_t(j)]; }  // C_jj, m/N

    // RT: C scaled by `scale` from the configured one (1/r^2 when every frequency is scaled by r).
    void rescale(double scale, const std::vector<ContactPoint>& contacts);
    // RT: g^{n+1} and delta^{n+1} = C g^{n+1} from the points' slopes G (f = -G).
    void advance(const double* slope);
    // RT: no deflection at n and n-1.
    void reset();
    double delta(int j) const { return delta_[size_t(j)]; }          // n
    double deltaPrev(int j) const { return deltaPrev_[size_t(j)]; }  // n-1
    // kappa delta^{n-1}_j: how far the force-free spring would carry point j's deflection back.
    double restoring(int j) const { return kappa_ * deltaPrev_[size_t(j)]; }
    // The spring's energy between n-1 and n: (g^n . delta^n + g^{n-1} . delta^{n-1}) / 4. RT.
    double energy() const;

    // Point j's spring as a caller that steps it elsewhere needs it (LinearStringBank): advance()
    // is delta^{n+1} = -(kappa - 1) delta^{n-1} - K_jj G_j and g^{n+1} = -(kappa - 1) g^{n-1} -
    // kappa w_j G_j for a point alone (K = coupling()), and its state (delta, g at n and n-1). RT.
    struct PointState
    {
        double delta = 0.0, deltaPrev = 0.0, force = 0.0, forcePrev = 0.0;
    };
    double kappa() const { return kappa_; }
    double pushPerSlope(int j) const { return active() ? coupling_(j, j) : 0.0; }  // K_jj
    double forcePerSlope(int j) const { return active() ? kappa_ * weights_[size_t(j)] : 0.0; }
    PointState pointState(int j) const
    {
        if (!active())
            return {};
        return {delta_[size_t(j)], deltaPrev_[size_t(j)], force_[size_t(j)], forcePrev_[size_t(j)]};
    }
    void setPointState(int j, const PointState& state)
    {
        if (!active())
            return;
        delta_[size_t(j)] = state.delta;
        deltaPrev_[size_t(j)] = state.deltaPrev;
        force_[size_t(j)] = state.force;
        forcePrev_[size_t(j)] = state.forcePrev;
    }

private:
    int P_ = 0;
    double kappa_ = 1.0;      // 2 / (1 + theta)
    Eigen::MatrixXd baseC_;     // as configured (rescale starts from it)
    Eigen::MatrixXd coupling_;  // kappa C W, column-major
    std::vector<double> weights_;
    std::vector<double> delta_, deltaPrev_;  // C g at n and n-1 (m)
    std::vector<double> force_, forcePrev_;  // g at n and n-1 (N)
};

}  // namespace jawari
