#include "physics/Polarisations.h"

#include "physics/StringModel.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace jawari
{

namespace
{
// A vector over one polarisation's M modes, laid over 2M: `first` times it, then `second` times it.
std::vector<double> overBoth(const std::vector<double>& v, double first, double second)
{
    std::vector<double> out(2 * v.size(), 0.0);
    for (size_t p = 0; p < v.size(); ++p)
    {
        out[p] = first * v[p];
        out[v.size() + p] = second * v[p];
    }
    return out;
}

std::vector<double> shapeAt(double L, int M, double x)
{
    std::vector<double> phi(static_cast<size_t>(M));
    for (int p = 0; p < M; ++p)
        phi[size_t(p)] = modeShape(L, p + 1, x);
    return phi;
}

ModalTable bothTables(const ModalTable& vertical, const SecondPolarisation& second)
{
    ModalTable t = vertical;
    for (int p = 0; p < vertical.size(); ++p)
    {
        t.frequencyHz.push_back(vertical.frequencyHz[size_t(p)] * (1.0 + second.detuning));
        t.omega.push_back(vertical.omega[size_t(p)] * (1.0 + second.detuning));
        t.sigma.push_back(vertical.sigma[size_t(p)] * second.dampingScale);
    }
    return t;
}
}  // namespace

ModalSolverConfig twoPolarisationConfig(const ModalSolverConfig& vertical, const SecondPolarisation& second)
{
    if (vertical.transform || !vertical.contactCompliance.empty() || !vertical.contactShapes.empty())
        throw std::invalid_argument("two polarisations take the projection path without a residual compliance");
    const auto& k = second.coupling;
    if (!(k.stiffness >= 0.0) || !std::isfinite(k.angle) || !(second.detuning > -1.0) || !(second.dampingScale >= 0.0))
        throw std::invalid_argument("two polarisations: the coupling's stiffness must be >= 0, its angle finite, the "
                                    "detuning above -1 and the damping scale >= 0");
    const int M = vertical.modes.size();
    const double L = vertical.lengthMetres;
    ModalSolverConfig c = vertical;
    c.modes = bothTables(vertical.modes, second);
    for (const auto& point : vertical.contacts)
    {
        const auto row = overBoth(shapeAt(L, M, point.position), 1.0, 0.0);
        c.contactShapes.insert(c.contactShapes.end(), row.begin(), row.end());
    }
    if (k.stiffness > 0.0)
    {
        if (!(k.position > 0.0 && k.position < L))
            throw std::invalid_argument("two polarisations: the coupling must lie on the string");
        const auto row = overBoth(shapeAt(L, M, k.position), std::cos(k.angle), std::sin(k.angle));
        for (const double sign : {1.0, -1.0})
        {
            c.contacts.push_back({k.position, 1.0, 0.0, ContactLaw{k.stiffness, 1.0}, -1});
            for (const double v : row)
                c.contactShapes.push_back(sign * v);
        }
    }
    // A pluck's shape: cos of it in the vertical, sin in the horizontal.
    c.shapeToModes.assign(size_t(2 * M) * M, 0.0);
    for (int p = 0; p < M; ++p)
    {
        c.shapeToModes[size_t(p) * M + p] = std::cos(second.excitationAngle);
        c.shapeToModes[size_t(M + p) * M + p] = std::sin(second.excitationAngle);
    }
    c.pickupWeights = overBoth(vertical.pickupWeights, 1.0, 0.0);
    if (!vertical.secondPickupWeights.empty())
        c.secondPickupWeights = overBoth(vertical.secondPickupWeights, 1.0, 0.0);
    if (vertical.excitationPosition)
    {
        const auto phi = vertical.excitationShape.empty() ? shapeAt(L, M, *vertical.excitationPosition)
                                                          : vertical.excitationShape;
        c.excitationShape =
            overBoth(phi, std::cos(second.excitationAngle), std::sin(second.excitationAngle));
    }
    return c;
}

CoupledModes coupledModesConfig(const ModalSolverConfig& vertical, const SecondPolarisation& second)
{
    SecondPolarisation uncoupled = second;
    uncoupled.coupling.stiffness = 0.0;
    CoupledModes out{twoPolarisationConfig(vertical, uncoupled), {}};
    // twoPolarisationConfig checked the rest; the spring's own values:
    const auto& k = second.coupling;
    if (k.stiffness > 0.0 && !(k.position > 0.0 && k.position < vertical.lengthMetres))
        throw std::invalid_argument("two polarisations: the coupling must lie on the string");
    auto& c = out.config;
    const int N = c.modes.size(), M = N / 2;
    const auto r = overBoth(shapeAt(vertical.lengthMetres, M, k.position), std::cos(k.angle), std::sin(k.angle));
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(N, N);
    for (int p = 0; p < N; ++p)
        A(p, p) = c.modes.omega[size_t(p)] * c.modes.omega[size_t(p)];
    const Eigen::Map<const Eigen::VectorXd> rv(r.data(), N);
    if (k.stiffness > 0.0)
        A.noalias() += (k.stiffness / c.linearDensity) * rv * rv.transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(A);
    if (eigen.info() != Eigen::Success || !(eigen.eigenvalues().minCoeff() > 0.0))
        throw std::runtime_error("two polarisations: the coupled string's modes were not found");
    const Eigen::MatrixXd& V = eigen.eigenvectors();
    out.basis.assign(V.data(), V.data() + size_t(N) * N);
    ModalTable modes;
    for (int k2 = 0; k2 < N; ++k2)
    {
        const double w = std::sqrt(eigen.eigenvalues()(k2));
        double sigma = 0.0;
        for (int p = 0; p < N; ++p)
            sigma += V(p, k2) * V(p, k2) * c.modes.sigma[size_t(p)];
        modes.omega.push_back(w);
        modes.frequencyHz.push_back(w / (2.0 * std::numbers::pi));
        modes.sigma.push_back(sigma);
    }
    c.modes = modes;
    auto carry = [&](std::vector<double>& v) {
        if (v.empty())
            return;
        const Eigen::VectorXd moved = V.transpose() * Eigen::Map<const Eigen::VectorXd>(v.data(), N);
        v.assign(moved.data(), moved.data() + N);
    };
    for (size_t j = 0; j < c.contacts.size(); ++j)
    {
        std::vector<double> row(c.contactShapes.begin() + long(j) * N, c.contactShapes.begin() + long(j + 1) * N);
        carry(row);
        std::copy(row.begin(), row.end(), c.contactShapes.begin() + long(j) * N);
    }
    carry(c.pickupWeights);
    carry(c.secondPickupWeights);
    carry(c.excitationShape);
    const int m = M;  // the shapes' sine modes: B' = V^T B
    const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> B(
        c.shapeToModes.data(), N, m);
    const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> moved = V.transpose() * B;
    c.shapeToModes.assign(moved.data(), moved.data() + size_t(N) * m);
    return out;
}

std::vector<double> CoupledModes::fromPolarisations(const std::vector<double>& q) const
{
    const int N = static_cast<int>(q.size());
    if (basis.size() != size_t(N) * N)
        throw std::invalid_argument("the state has the wrong number of modes for these coupled modes");
    const Eigen::Map<const Eigen::MatrixXd> V(basis.data(), N, N);
    const Eigen::VectorXd moved = V.transpose() * Eigen::Map<const Eigen::VectorXd>(q.data(), N);
    return {moved.data(), moved.data() + N};
}

double modeRangeEnergy(ModalSolver& solver, int first, int count)
{
    const auto now = solver.modalState(false), before = solver.modalState(true);
    const auto& c = solver.coefficients();
    const double dt = solver.timeStep();
    double sum = 0.0;
    for (int p = first; p < first + count; ++p)
    {
        const double v = (now[size_t(p)] - before[size_t(p)]) / dt;
        sum += c[size_t(p)].kineticWeight * v * v + c[size_t(p)].potentialWeight * now[size_t(p)] * before[size_t(p)];
    }
    return 0.5 * solver.linearDensity() * sum;
}

}  // namespace jawari
