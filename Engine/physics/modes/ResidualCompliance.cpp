#include "physics/modes/ResidualCompliance.h"

#include <stdexcept>

namespace jawari
{

void ResidualCompliance::prepare(const std::vector<double>& compliance, const std::vector<ContactPoint>& contacts,
                                 double theta)
{
    P_ = static_cast<int>(contacts.size());
    delta_.assign(P_, 0.0);
    deltaPrev_.assign(P_, 0.0);
    force_.assign(P_, 0.0);
    forcePrev_.assign(P_, 0.0);
    weights_.resize(P_);
    for (int j = 0; j < P_; ++j)
        weights_[j] = contacts[j].weight;
    if (compliance.empty())
        return;
    if (compliance.size() != size_t(P_) * P_)
        throw std::invalid_argument("contact compliance must be P x P");
    if (!(theta >= 0.0 && theta <= 1.0))
        throw std::invalid_argument("the residual compliance's loss share theta must be in [0, 1]");
    kappa_ = 2.0 / (1.0 + theta);
    baseC_ = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(compliance.data(),
                                                                                                      P_, P_);
    coupling_.resize(P_, P_);
    rescale(1.0, contacts);
}

void ResidualCompliance::rescale(double scale, const std::vector<ContactPoint>& contacts)
{
    for (int i = 0; i < P_; ++i)
        for (int j = 0; j < P_; ++j)
            coupling_(i, j) = kappa_ * (scale * baseC_(i, j) * contacts[j].weight);
}

void ResidualCompliance::advance(const double* slope)
{
    if (!active())
        return;
    // An element loop, not std::copy/fill: P is mostly 1, where their calls cost more than the work.
    // The force-free part first: delta^{n+1} = -(kappa - 1) delta^{n-1}, g likewise.
    const double back = kappa_ - 1.0;
    for (int j = 0; j < P_; ++j)
    {
        const double d = delta_[j], g = force_[j];
        delta_[j] = -back * deltaPrev_[j];
        force_[j] = -back * forcePrev_[j];
        deltaPrev_[j] = d;
        forcePrev_[j] = g;
    }
    // Then kappa C W f = -kappa C W G, column by column over the points that press (most do not,
    // most of the time).
    for (int i = 0; i < P_; ++i)
        if (slope[i] != 0.0)
        {
            const double* column = coupling_.data() + static_cast<ptrdiff_t>(i) * P_;  // column-major
            const double g = slope[i];
            for (int j = 0; j < P_; ++j)
                delta_[j] -= column[j] * g;
            force_[i] -= kappa_ * weights_[i] * g;
        }
}

void ResidualCompliance::reset()
{
    std::fill(delta_.begin(), delta_.end(), 0.0);
    std::fill(deltaPrev_.begin(), deltaPrev_.end(), 0.0);
    std::fill(force_.begin(), force_.end(), 0.0);
    std::fill(forcePrev_.begin(), forcePrev_.end(), 0.0);
}

double ResidualCompliance::energy() const
{
    if (!active())
        return 0.0;
    double sum = 0.0;
    for (int j = 0; j < P_; ++j)
        sum += force_[j] * delta_[j] + forcePrev_[j] * deltaPrev_[j];
    return 0.25 * sum;
}

}  // namespace jawari
