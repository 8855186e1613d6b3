#include "physics/ResidualCompliance.h"

#include <stdexcept>

namespace jawari
{

void ResidualCompliance::prepare(const std::vector<double>& compliance, const std::vector<ContactPoint>& contacts)
{
    P_ = static_cast<int>(contacts.size());
    delta_.assign(P_, 0.0);
    deltaPrev_.assign(P_, 0.0);
    if (compliance.empty())
        return;
    if (compliance.size() != size_t(P_) * P_)
        throw std::invalid_argument("contact compliance must be P x P");
    baseC_ = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(compliance.data(),
                                                                                                      P_, P_);
    complianceW_ = baseC_;
    for (int j = 0; j < P_; ++j)
        complianceW_.col(j) *= contacts[j].weight;
    inverse_ = baseC_.inverse();
    baseInverse_ = inverse_;
}

void ResidualCompliance::rescale(double scale, const std::vector<ContactPoint>& contacts)
{
    for (int i = 0; i < P_; ++i)
        for (int j = 0; j < P_; ++j)
        {
            complianceW_(i, j) = scale * baseC_(i, j) * contacts[j].weight;
            inverse_(i, j) = baseInverse_(i, j) / scale;  // no Eigen inverse on the audio thread
        }
}

void ResidualCompliance::advance(const double* slope)
{
    if (!active())
        return;
    // An element loop, not std::copy/fill: P is mostly 1, where their calls cost more than the work.
    for (int j = 0; j < P_; ++j)
    {
        deltaPrev_[j] = delta_[j];
        delta_[j] = 0.0;
    }
    // delta = -C W G, column by column over the points that press (most do not, most of the time).
    for (int i = 0; i < P_; ++i)
        if (slope[i] != 0.0)
        {
            const double* column = complianceW_.data() + static_cast<ptrdiff_t>(i) * P_;  // column-major
            const double g = slope[i];
            for (int j = 0; j < P_; ++j)
                delta_[j] -= column[j] * g;
        }
}

void ResidualCompliance::reset()
{
    std::fill(delta_.begin(), delta_.end(), 0.0);
    std::fill(deltaPrev_.begin(), deltaPrev_.end(), 0.0);
}

double ResidualCompliance::energy() const
{
    if (!active())
        return 0.0;
    // d^T C^-1 d by loops: Eigen's d.dot(C^-1 d) makes its product in a heap temporary, and the
    // solver measures this energy on the audio thread (its points out of reach).
    auto quadratic = [&](const std::vector<double>& d) {
        double sum = 0.0;
        for (int j = 0; j < P_; ++j)
        {
            double row = 0.0;
            for (int i = 0; i < P_; ++i)
                row += inverse_(j, i) * d[size_t(i)];
            sum += d[size_t(j)] * row;
        }
        return sum;
    };
    return 0.25 * (quadratic(delta_) + quadratic(deltaPrev_));
}

}  // namespace jawari
