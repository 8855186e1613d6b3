#include "physics/contact/ContactReach.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace jawari
{

void ContactReach::prepare(int points, int modes, bool enabled)
{
    enabled_ = enabled;
    reach_.assign(size_t(points), std::numeric_limits<double>::infinity());
    tail_.assign(size_t(points), std::numeric_limits<double>::infinity());
    radius_ = std::numeric_limits<double>::infinity();
    kappa_.edit().assign(size_t(modes), 0.0);
    live_.assign(size_t(points), 1);
    liveRows_.resize(size_t(points));
    for (int j = 0; j < points; ++j)
        liveRows_[size_t(j)] = j;
    liveCount_ = points;
}

// reach_j = sqrt((2/mu) sum_p phi_p(x_j)^2 kappa_p^2) + 2 sqrt(C_jj) for every point, so that a string of
// energy H has |u_j + delta_j| <= sqrt(H) reach_j. Mode p's share of H^{n-1/2} is
//   E_p = (mu/2) (C1 (q^n - q^{n-1})^2 / dt^2 + C2 q^n q^{n-1}) = (mu/2) (a D^2 + (C2/4) S^2)
// with D = q^n - q^{n-1}, S = q^n + q^{n-1}, a = C1/dt^2 - C2/4 (both weights positive for a stable mode),
// so |q^n| <= (|S| + |D|)/2 <= sqrt(2 E_p / mu) kappa_p, kappa_p = 1/sqrt(C2) + 1/(2 sqrt(a)) (the larger of
// the two coefficient sets'); Cauchy-Schwarz over the modes gives the first term. The dropped modes'
// spring holds delta^T C^-1 delta / 4 <= H, so |delta_j| <= 2 sqrt(H C_jj).
void ContactReach::measure(const std::vector<ExactModeCoefficients>& normal,
                           const std::vector<ExactModeCoefficients>& released, const std::vector<double>& shapes,
                           double dt, double mu, const ResidualCompliance& compliance,
                           const std::vector<ContactPoint>& contacts)
{
    if (!enabled_)
        return;
    auto kappa = [&](const ExactModeCoefficients& c) {
        const double a = c.kineticWeight / (dt * dt) - 0.25 * c.potentialWeight;
        if (!(c.potentialWeight > 0.0) || !(a > 0.0))
            return std::numeric_limits<double>::infinity();
        return 1.0 / std::sqrt(c.potentialWeight) + 0.5 / std::sqrt(a);
    };
    // Once per mode (two square roots and two divisions each), not once per point and mode: a note's
    // start retunes its string.
    const size_t M = kappa_.size();
    auto& kappas = kappa_.edit();
    for (size_t p = 0; p < M; ++p)
        kappas[p] = std::max(kappa(normal[p]), kappa(released[p]));
    for (size_t j = 0; j < contacts.size(); ++j)
    {
        const double spring =
            compliance.active() ? std::max(compliance.diagonal(int(j)), 0.0) : 0.0;
        reach_[j] = modesReach(shapes.data() + j * M, nullptr, int(M), mu) + 2.0 * std::sqrt(spring);
    }
}

void ContactReach::measureTail(const int* tailModes, int count, const std::vector<double>& shapes, double mu)
{
    if (!enabled_)
        return;
    const size_t M = kappa_.size();
    for (size_t j = 0; j < tail_.size(); ++j)
        tail_[j] = modesReach(shapes.data() + j * M, tailModes, count, mu);
}

// sqrt((2/mu) sum_p phi_p^2 kappa_p^2) over a point's row of shapes, for the `count` modes `modes`
// (null: the first `count`).
double ContactReach::modesReach(const double* row, const int* modes, int count, double mu) const
{
    double sum = 0.0;
    for (int i = 0; i < count; ++i)
    {
        const size_t p = modes != nullptr ? size_t(modes[i]) : size_t(i);
        const double k = kappa_[p];
        const double phi = row[p];
        sum += phi == 0.0 ? 0.0 : phi * phi * k * k;
    }
    return std::sqrt(2.0 * sum / mu);
}

double ContactReach::reachRadius(double H)
{
    return 1.05 * std::sqrt(std::max(H, 0.0));
}

}  // namespace jawari
