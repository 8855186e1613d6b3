// The coupled string's normal modes (Engine/physics/string/RankOneEigen.h, Polarisations.h): the
// eigenpairs of Omega^2 + (K/mu) r r^T from the secular equation agree with a dense symmetric
// eigensolver's, are orthonormal to working precision, and each eigenvalue is the secular
// equation's root to a few ulps (which the dense solver, accurate to eps |A| only, is not for the
// low modes); the deflations (a spring at a node, equal frequencies) keep all of it.

#include "TestSupport.h"
#include "physics/string/Polarisations.h"
#include "physics/string/RankOneEigen.h"
#include "physics/string/StringDiscretisation.h"

#include <Eigen/Dense>
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

using namespace jawari;

namespace
{
// The coupled string's problem: d = omega_p^2 over both polarisations (the horizontal's detuned),
// r the spring's direction times the modes' shapes at it, c = K/mu.
struct CoupledProblem
{
    std::vector<double> d, r;
    double c = 0.0;
};

CoupledProblem coupledProblem(int M, double detuning, const PolarisationCoupling& coupling)
{
    const auto s = test::paperString();
    const auto table = buildModalTable(s, M);
    CoupledProblem out;
    out.d.resize(size_t(2 * M));
    out.r.resize(size_t(2 * M));
    for (int p = 0; p < M; ++p)
    {
        const double w = table.omega[size_t(p)], phi = modeShape(s.lengthMetres, p + 1, coupling.position);
        out.d[size_t(p)] = w * w;
        const double horizontal = w * (1.0 + detuning);
        out.d[size_t(M + p)] = horizontal * horizontal;
        out.r[size_t(p)] = std::cos(coupling.angle) * phi;
        out.r[size_t(M + p)] = std::sin(coupling.angle) * phi;
    }
    out.c = coupling.stiffness / s.linearDensity;
    return out;
}

// The instrument's coupling (instrumentSecondPolarisation) on the paper's string.
PolarisationCoupling instrumentCoupling()
{
    const auto s = test::paperString();
    return {s.lengthMetres - 0.01, std::numbers::pi / 6, 0.1 * s.tensionNewtons / 0.01};
}

Eigen::MatrixXd denseMatrix(const CoupledProblem& problem)
{
    const long N = long(problem.d.size());
    const Eigen::Map<const Eigen::VectorXd> r(problem.r.data(), N);
    Eigen::MatrixXd A = problem.c * r * r.transpose();
    A.diagonal() += Eigen::Map<const Eigen::VectorXd>(problem.d.data(), N);
    return A;
}

struct Agreement
{
    double eigenvalues = 0.0;     // max |lambda - lambda_dense| / |A|
    double orthogonality = 0.0;   // max |V^T V - I|
    double residual = 0.0;        // max |A v - lambda v| / |A|
    double worstAlignment = 0.0;  // min over well-separated eigenvalues of |<v, v_dense>|, subtracted from 1
    int separated = 0;            // how many were compared
    bool signs = true;            // every column's largest-magnitude component positive
    bool finite = true;
};

Agreement compareWithDense(const CoupledProblem& problem)
{
    const long N = long(problem.d.size());
    const auto eigen = rankOneUpdateEigen(problem.d, problem.r, problem.c);
    const Eigen::MatrixXd A = denseMatrix(problem);
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> dense(A);
    const Eigen::Map<const Eigen::MatrixXd> V(eigen.eigenvectors.data(), N, N);
    const Eigen::Map<const Eigen::VectorXd> lambda(eigen.eigenvalues.data(), N);
    const double norm = dense.eigenvalues().cwiseAbs().maxCoeff();
    Agreement a;
    a.finite = V.allFinite() && lambda.allFinite();
    a.eigenvalues = (lambda - dense.eigenvalues()).cwiseAbs().maxCoeff() / norm;
    a.orthogonality = (V.transpose() * V - Eigen::MatrixXd::Identity(N, N)).cwiseAbs().maxCoeff();
    a.residual = (A * V - V * lambda.asDiagonal()).colwise().norm().maxCoeff() / norm;
    for (long k = 0; k < N; ++k)
    {
        long largest = 0;
        V.col(k).cwiseAbs().maxCoeff(&largest);
        a.signs = a.signs && V(largest, k) > 0.0;
        const double below = k > 0 ? lambda(k) - lambda(k - 1) : norm, above = k + 1 < N ? lambda(k + 1) - lambda(k) : norm;
        if (std::min(below, above) < 1e-6 * norm)
            continue;
        ++a.separated;
        a.worstAlignment = std::max(a.worstAlignment, 1.0 - std::abs(V.col(k).dot(dense.eigenvectors().col(k))));
    }
    return a;
}

void checkAgreement(const CoupledProblem& problem, int minimumSeparated)
{
    const auto a = compareWithDense(problem);
    INFO("N = " << problem.d.size() << ": eigenvalues " << a.eigenvalues << " of |A| from the dense solver's, |V^T V - I| "
                << a.orthogonality << ", |A V - V Lambda| " << a.residual << " of |A|, 1 - |<v, v_dense>| "
                << a.worstAlignment << " over " << a.separated << " well-separated modes");
    CHECK(a.finite);
    CHECK(a.eigenvalues < 1e-12);
    CHECK(a.orthogonality < 1e-12);
    CHECK(a.residual < 1e-13);
    CHECK(a.worstAlignment < 1e-9);
    CHECK(a.separated >= minimumSeparated);
    CHECK(a.signs);
}

// The roots of f(lambda) = 1 + c sum_p r_p^2 / (d_p - lambda), one between consecutive poles and
// one above the last, by bisection in long double: the reference for distinct, weighted poles.
std::vector<long double> secularRootsByBisection(const CoupledProblem& problem)
{
    std::vector<long double> d(problem.d.begin(), problem.d.end()), w2;
    std::sort(d.begin(), d.end());
    long double rho = 0.0L;
    for (const double r : problem.r)
        rho += (long double)problem.c * r * r;
    std::vector<long double> roots;
    auto f = [&](long double lambda) {
        long double sum = 1.0L;
        for (size_t p = 0; p < problem.d.size(); ++p)
            sum += (long double)problem.c * problem.r[p] * problem.r[p] / ((long double)problem.d[p] - lambda);
        return sum;
    };
    for (size_t k = 0; k < d.size(); ++k)
    {
        long double lo = d[k], hi = k + 1 < d.size() ? d[k + 1] : d[k] + rho;
        for (int i = 0; i < 200 && hi - lo > 0.0L; ++i)
        {
            const long double mid = 0.5L * (lo + hi);
            if (mid == lo || mid == hi)
                break;
            (f(mid) < 0.0L ? lo : hi) = mid;
        }
        roots.push_back(0.5L * (lo + hi));
    }
    return roots;
}
}  // namespace

TEST_CASE("The coupled modes from the secular equation agree with the dense eigensolver's on the instrument's "
          "coupling, orthonormal to 1e-12",
          "[polarisations][coupled modes]")
{
    const int M = GENERATE(20, 200, 600);
    INFO("M = " << M);
    // Every mode but the closest pairs (the polarisations' 1e-3 detuning of the low modes) compared.
    checkAgreement(coupledProblem(M, 1e-3, instrumentCoupling()), M);
}

TEST_CASE("Each coupled mode's eigenvalue is its secular equation's root to 2e-15, the lowest modes' too",
          "[polarisations][coupled modes]")
{
    const auto problem = coupledProblem(200, 1e-3, instrumentCoupling());
    const auto eigen = rankOneUpdateEigen(problem.d, problem.r, problem.c);
    const auto roots = secularRootsByBisection(problem);
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> dense(denseMatrix(problem), Eigen::EigenvaluesOnly);
    double worst = 0.0, denseWorst = 0.0;
    for (size_t k = 0; k < roots.size(); ++k)
    {
        worst = std::max(worst, double(std::abs(eigen.eigenvalues[k] - roots[k]) / roots[k]));
        denseWorst = std::max(denseWorst, double(std::abs(dense.eigenvalues()(long(k)) - roots[k]) / roots[k]));
    }
    INFO("relative error " << worst << ", the dense solver's " << denseWorst);
    CHECK(worst < 2e-15);
}

TEST_CASE("The coupled modes deflate a spring at the modes' nodes, equal frequencies and a spring without "
          "stiffness, and still agree with the dense eigensolver's",
          "[polarisations][coupled modes]")
{
    const auto s = test::paperString();
    SECTION("a spring at the middle, a node of every even mode (phi ~ 1e-13, not 0): those keep their modes")
    {
        auto coupling = instrumentCoupling();
        coupling.position = (0.5 + 1e-15) * s.lengthMetres;
        const auto problem = coupledProblem(200, 1e-3, coupling);
        checkAgreement(problem, 200);
        const auto eigen = rankOneUpdateEigen(problem.d, problem.r, problem.c);
        // Deflated: the frequency and the shape exactly, the mode itself (one component 1, the rest 0).
        int unmoved = 0;
        const size_t N = problem.d.size();
        for (size_t k = 0; k < N; ++k)
        {
            const auto first = eigen.eigenvectors.begin() + long(k * N), last = first + long(N);
            const auto one = std::find(first, last, 1.0);
            const bool unit = one != last && std::count(first, last, 0.0) == long(N) - 1;
            unmoved += unit && eigen.eigenvalues[k] == problem.d[size_t(one - first)] ? 1 : 0;
        }
        CHECK(unmoved == 200);  // the even modes, both polarisations
    }
    SECTION("no detuning: each mode's two polarisations have one frequency, the spring's perpendicular keeps it")
    {
        const auto problem = coupledProblem(200, 0.0, instrumentCoupling());
        checkAgreement(problem, 150);
        const auto eigen = rankOneUpdateEigen(problem.d, problem.r, problem.c);
        int unmoved = 0;
        for (int p = 0; p < 200; ++p)
            for (const double lambda : eigen.eigenvalues)
                unmoved += std::abs(lambda - problem.d[size_t(p)]) <= 4e-16 * problem.d[size_t(p)] ? 1 : 0;
        CHECK(unmoved == 200);
    }
    SECTION("no stiffness: the modes are the polarisations' own, sorted")
    {
        auto coupling = instrumentCoupling();
        coupling.stiffness = 0.0;
        const auto problem = coupledProblem(200, 1e-3, coupling);
        checkAgreement(problem, 0);
        const auto eigen = rankOneUpdateEigen(problem.d, problem.r, problem.c);
        auto sorted = problem.d;
        std::sort(sorted.begin(), sorted.end());
        CHECK(eigen.eigenvalues == sorted);
    }
}

TEST_CASE("Diagonal plus rank one in general: clustered poles and weights over eight decades keep the eigenpairs "
          "orthonormal and exact to 1e-13",
          "[polarisations][coupled modes]")
{
    // d ascending by gaps of 10^-(0..G) (clusters down to 1e-13 apart, some deflated, some not),
    // weights of 10^-(0..W), both signs.
    std::mt19937_64 random(7);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    for (const double gaps : {4.0, 7.0, 10.0, 13.0})
        for (const double weights : {2.0, 5.0, 8.0})
        {
            CoupledProblem problem;
            problem.c = 1.0;
            double d = 1.0;
            for (int p = 0; p < 300; ++p)
            {
                d += std::pow(10.0, -gaps * uniform(random));
                problem.d.push_back(d);
                problem.r.push_back(std::pow(10.0, -weights * uniform(random)) * (uniform(random) < 0.5 ? -1.0 : 1.0));
            }
            const auto a = compareWithDense(problem);
            INFO("gaps to 1e-" << gaps << ", weights to 1e-" << weights << ": |V^T V - I| " << a.orthogonality
                               << ", |A V - V Lambda| " << a.residual << " of |A|, eigenvalues " << a.eigenvalues);
            CHECK(a.finite);
            CHECK(a.orthogonality < 1e-13);
            CHECK(a.residual < 1e-13);
            CHECK(a.eigenvalues < 1e-13);
            CHECK(a.signs);
        }
}

TEST_CASE("The coupled string's configuration carries its rows, pickups, excitation and pluck map into the modes "
          "as the dense products V^T x do",
          "[polarisations][coupled modes]")
{
    const auto s = test::paperString();
    const int M = 120;
    auto one = stringSolverConfig(s, {test::pointObstacle(0.006)}, M, 1e6, 0.992, PickupQuantity::displacement);
    one.excitationPosition = 0.3;
    SecondPolarisation second;
    second.detuning = 1e-3;
    second.excitationAngle = 0.4;
    second.coupling = instrumentCoupling();
    auto uncoupled = second;
    uncoupled.coupling.stiffness = 0.0;
    const auto plain = twoPolarisationConfig(one, uncoupled);
    const auto coupled = coupledModesConfig(one, second);
    const long N = 2 * M;
    const Eigen::Map<const Eigen::MatrixXd> V(coupled.basis.data(), N, N);
    // max |moved - V^T original| / max |original| over the vectors of length N laid one after another.
    auto distance = [&](const std::vector<double>& moved, const std::vector<double>& original) {
        const long count = long(original.size()) / N;
        const Eigen::Map<const Eigen::MatrixXd> after(moved.data(), N, count), before(original.data(), N, count);
        return (after - V.transpose() * before).cwiseAbs().maxCoeff() / before.cwiseAbs().maxCoeff();
    };
    CHECK(distance(coupled.config.contactShapes, plain.contactShapes) < 1e-14);
    CHECK(distance(coupled.config.pickupWeights, plain.pickupWeights) < 1e-14);
    CHECK(distance(coupled.config.excitationShape, plain.excitationShape) < 1e-14);
    // The pluck's map, N x M by rows: V^T B.
    using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    const Eigen::Map<const RowMajor> map(coupled.config.shapeToModes.data(), N, M), B(plain.shapeToModes.data(), N, M);
    CHECK((map - V.transpose() * B).cwiseAbs().maxCoeff() < 1e-14);
    const auto problem = coupledProblem(M, 1e-3, second.coupling);
    const auto eigen = rankOneUpdateEigen(problem.d, problem.r, problem.c);
    for (long k = 0; k < N; ++k)
    {
        double sigma = 0.0;
        for (long p = 0; p < N; ++p)
            sigma += V(p, k) * V(p, k) * plain.modes.sigma[size_t(p)];
        CHECK(coupled.config.modes.sigma[size_t(k)] == Approx(sigma).epsilon(1e-12));
        CHECK(coupled.config.modes.omega[size_t(k)] == std::sqrt(eigen.eigenvalues[size_t(k)]));
    }
}
