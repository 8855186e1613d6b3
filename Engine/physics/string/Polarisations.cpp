#include "physics/string/Polarisations.h"

#include "physics/string/RankOneEigen.h"
#include "physics/string/StringModel.h"

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

// The obstacles' rows, the pickups and the excitation into the coupled modes (V^T times each, as
// one product), and the pluck's map B = [cos(a) I; sin(a) I] (twoPolarisationConfig's) by its
// structure: (V^T B)_kp = cos(a) V_pk + sin(a) V_(M+p)k.
void carryIntoModes(ModalSolverConfig& c, const Eigen::Map<const Eigen::MatrixXd>& V, double excitationAngle)
{
    const long N = V.rows(), P = long(c.contacts.size()), M = N / 2;
    std::vector<std::vector<double>*> vectors;
    for (auto* v : {&c.pickupWeights, &c.secondPickupWeights, &c.excitationShape})
        if (!v->empty())
            vectors.push_back(v);
    using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    RowMajor rows(P + long(vectors.size()), N);
    rows.topRows(P) = Eigen::Map<const RowMajor>(c.contactShapes.data(), P, N);
    for (size_t i = 0; i < vectors.size(); ++i)
        rows.row(P + long(i)) = Eigen::Map<const Eigen::RowVectorXd>(vectors[i]->data(), N);
    const RowMajor moved = rows * V;
    std::copy(moved.data(), moved.data() + P * N, c.contactShapes.begin());
    for (size_t i = 0; i < vectors.size(); ++i)
        std::copy(moved.row(P + long(i)).data(), moved.row(P + long(i)).data() + N, vectors[i]->begin());
    const double along = std::cos(excitationAngle), across = std::sin(excitationAngle);
    c.shapeToModes.assign(size_t(N) * M, 0.0);
    for (long j = 0; j < N; ++j)
        for (long p = 0; p < M; ++p)
            c.shapeToModes[size_t(j * M + p)] = along * V(p, j) + across * V(M + p, j);
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
    const int N = c.modes.size();
    // Omega^2 + (K/mu) r r^T: a diagonal and a rank-one update, its eigenpairs in O(N^2).
    std::vector<double> omega2(static_cast<size_t>(N));
    for (int p = 0; p < N; ++p)
        omega2[size_t(p)] = c.modes.omega[size_t(p)] * c.modes.omega[size_t(p)];
    const auto r = overBoth(shapeAt(vertical.lengthMetres, N / 2, k.position), std::cos(k.angle), std::sin(k.angle));
    auto eigen = rankOneUpdateEigen(omega2, r, k.stiffness > 0.0 ? k.stiffness / c.linearDensity : 0.0);
    if (!(eigen.eigenvalues.front() > 0.0))
        throw std::runtime_error("two polarisations: the coupled string's modes were not found");
    out.basis = std::move(eigen.eigenvectors);
    const Eigen::Map<const Eigen::MatrixXd> V(out.basis.data(), N, N);
    ModalTable modes;
    for (int j = 0; j < N; ++j)
    {
        const double w = std::sqrt(eigen.eigenvalues[size_t(j)]);
        double sigma = 0.0;
        for (int p = 0; p < N; ++p)
            sigma += V(p, j) * V(p, j) * c.modes.sigma[size_t(p)];
        modes.omega.push_back(w);
        modes.frequencyHz.push_back(w / (2.0 * std::numbers::pi));
        modes.sigma.push_back(sigma);
    }
    c.modes = modes;
    carryIntoModes(c, V, second.excitationAngle);
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
