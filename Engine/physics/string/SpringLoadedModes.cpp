#include "physics/string/SpringLoadedModes.h"

#include <Eigen/Dense>

#include <cmath>
#include <numbers>

namespace jawari
{
namespace
{
// U with U U^T = S^T K S / mu: S the bilateral points' rows (P x N), K their stiffness w_j K_j in
// series with the modes the solver dropped (its residual compliance C, m/N, on those points):
// K = (K_points^{-1} + C)^{-1}, as the contact solve meets them at low frequency.
Eigen::MatrixXd springRows(const ModalSolverConfig& c)
{
    const int N = c.modes.size();
    const int P = static_cast<int>(c.contacts.size());
    std::vector<int> bilateral;
    for (int j = 0; j < P; ++j)
        if (c.contacts[size_t(j)].law.bilateral)
            bilateral.push_back(j);
    const auto B = static_cast<Eigen::Index>(bilateral.size());
    Eigen::MatrixXd S(B, N);
    Eigen::MatrixXd compliance = Eigen::MatrixXd::Zero(B, B);
    for (Eigen::Index a = 0; a < B; ++a)
    {
        const int j = bilateral[size_t(a)];
        const auto& point = c.contacts[size_t(j)];
        for (int p = 0; p < N; ++p)
            S(a, p) = c.contactShapes.empty() ? modeShape(c.lengthMetres, p + 1, point.position)
                                              : c.contactShapes[size_t(j) * N + p];
        compliance(a, a) = 1.0 / (point.weight * point.law.stiffness);
        if (!c.contactCompliance.empty())
            for (Eigen::Index b = 0; b < B; ++b)
                compliance(a, b) += c.contactCompliance[size_t(j) * P + size_t(bilateral[size_t(b)])];
    }
    const Eigen::MatrixXd stiffness = compliance.inverse() / c.linearDensity;
    return S.transpose() * Eigen::LLT<Eigen::MatrixXd>(stiffness).matrixL().toDenseMatrix();
}
}  // namespace

double springLoadedFrequencyHz(const ModalSolverConfig& config, int k)
{
    const Eigen::MatrixXd U = springRows(config);
    if (U.cols() == 0)
        return config.modes.frequencyHz[size_t(k)];
    const Eigen::Map<const Eigen::VectorXd> omega(config.modes.omega.data(), config.modes.size());
    const Eigen::VectorXd d = omega.array().square();
    auto rayleigh = [&](const Eigen::VectorXd& x) {
        return (d.array() * x.array().square()).sum() + (U.transpose() * x).squaredNorm();
    };
    Eigen::VectorXd x = Eigen::VectorXd::Unit(d.size(), k);
    double sigma = rayleigh(x);
    for (int iteration = 0; iteration < 50; ++iteration)
    {
        // y = (D + U U^T - sigma I)^{-1} x = z - Dinv U (I + U^T Dinv U)^{-1} U^T z, z = Dinv x.
        Eigen::VectorXd dInv = (d.array() - sigma).inverse();
        const Eigen::VectorXd z = dInv.cwiseProduct(x);
        const Eigen::MatrixXd S =
            Eigen::MatrixXd::Identity(U.cols(), U.cols()) + U.transpose() * dInv.asDiagonal() * U;
        const Eigen::VectorXd y = z - dInv.cwiseProduct(U * S.partialPivLu().solve(U.transpose() * z));
        if (!y.allFinite())
            break;  // sigma is an eigenvalue to rounding
        x = y.normalized();
        const double next = rayleigh(x);
        const bool converged = std::abs(next - sigma) <= 1e-15 * next;
        sigma = next;
        if (converged)
            break;
    }
    return std::sqrt(sigma) / (2.0 * std::numbers::pi);
}

}  // namespace jawari
