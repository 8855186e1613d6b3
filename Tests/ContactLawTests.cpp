// The regularised contact law, its discrete gradient and the safeguarded Newton (docs/design.md section 2).

#include "physics/contact/ContactLanes.h"
#include "physics/contact/ContactSpline.h"
#include "physics/contact/ContactLaw.h"
#include "physics/contact/ContactSystem.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>

using namespace jawari;

namespace
{
// P densely coupled points: A = k Phi Phi^T W from random mode shapes (symmetric positive
// semidefinite times diagonal) and random stiff laws, in a prepared ContactSystem.
struct DenseCoupling
{
    Eigen::MatrixXd A;
    std::vector<ContactPoint> points;
    ContactSystem system;

    DenseCoupling(int P, std::mt19937& rng)
    {
        std::uniform_real_distribution<double> unit(-1.0, 1.0);
        const Eigen::MatrixXd Phi = Eigen::MatrixXd::Random(P, 40);
        const Eigen::VectorXd w = (Eigen::VectorXd::Random(P).array() + 1.5) * 1e-3;
        const double k = std::pow(10.0, -11.0 + 2.0 * unit(rng));
        A = k * Phi * Phi.transpose() * w.asDiagonal();
        points.assign(size_t(P), {});
        for (auto& p : points)
            p.law = {std::pow(10.0, 8.0 + 6.0 * std::abs(unit(rng))), 1.0 + 2.0 * std::abs(unit(rng))};
        system.prepare(points, A);
    }

    // |r + A G - b|_inf relative to |b|_inf + |A G|_inf.
    double relativeResidual(const std::vector<double>& r, const Eigen::VectorXd& G, const std::vector<double>& b) const
    {
        const Eigen::Index P = A.rows();
        const Eigen::VectorXd AG = A * G;
        const Eigen::VectorXd residual =
            Eigen::Map<const Eigen::VectorXd>(r.data(), P) + AG - Eigen::Map<const Eigen::VectorXd>(b.data(), P);
        return residual.lpNorm<Eigen::Infinity>()
               / (Eigen::Map<const Eigen::VectorXd>(b.data(), P).lpNorm<Eigen::Infinity>()
                  + AG.lpNorm<Eigen::Infinity>());
    }
};

// Point a touches (at n-1 or with the contact-free prediction at n+1); every other point starts off
// the obstacle, clear of it at n+1 without the force by a margin from 1e-12 to 1e-6 m.
void onePointTouching(int a, std::mt19937& rng, std::vector<double>& s, std::vector<double>& b)
{
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    for (size_t j = 0; j < s.size(); ++j)
    {
        if (int(j) == a)
        {
            s[j] = 1e-5 * unit(rng);
            b[j] = s[j] - 1e-5 * std::abs(unit(rng));  // in contact at n+1 without the force
        }
        else
        {
            s[j] = -1e-6 * std::abs(unit(rng));
            b[j] = s[j] + 1e-6 * std::pow(10.0, -6.0 * std::abs(unit(rng)));
        }
    }
}
}  // namespace

TEST_CASE("the chord slope times r is the exact difference of potentials")
{
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    double worst = 0.0;
    for (double alpha : {1.0, 1.3, 2.0, 3.0, 4.0})
        for (int i = 0; i < 20000; ++i)
        {
            const ContactLaw law{1e13, alpha};
            const double s = 1e-6 * unit(rng);
            const double r = 1e-6 * unit(rng) * std::pow(10.0, -8.0 * std::abs(unit(rng)));
            const double dpsi = contactPotential(law, s - r) - contactPotential(law, s);
            const double Gr = chordSlope(law, s, r).value * r;
            const double scale = contactPotential(law, std::abs(s)) + contactPotential(law, std::abs(s - r)) + 1e-300;
            worst = std::max(worst, std::abs(Gr - dpsi) / scale);
        }
    INFO("worst relative mismatch " << worst);
    CHECK(worst < 1e-12);
}

TEST_CASE("the chord slope is nondecreasing and its derivative matches finite differences")
{
    const ContactLaw law{1e10, 1.5};
    const double s = 2e-6;
    double previous = -1e300;
    for (int i = -400; i <= 400; ++i)
    {
        const double r = i * 1e-8;
        const auto G = chordSlope(law, s, r);
        CHECK(G.value >= previous);
        CHECK(G.value <= 0.0);
        previous = G.value;
        const double h = 1e-12;
        const double fd = (chordSlope(law, s, r + h).value - chordSlope(law, s, r - h).value) / (2 * h);
        CHECK(G.derivative == Approx(fd).epsilon(1e-3).margin(1e-6 * std::abs(G.value) / s));
    }
}

TEST_CASE("the safeguarded Newton converges for K from 1e4 to 1e16 and alpha from 1 to 4")
{
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    int most = 0;
    double worstResidual = 0.0, worstPower = 0.0;
    long solves = 0, powers = 0;
    for (double logK = 4.0; logK <= 16.0; logK += 1.0)
        for (double alpha : {1.0, 1.3, 1.5, 2.0, 3.0, 4.0})
            for (int i = 0; i < 400; ++i)
            {
                const ContactLaw law{std::pow(10.0, logK), alpha};
                const double k = std::pow(10.0, -12.0 + 4.0 * unit(rng));  // dt^2/mu from ~2 MHz to ~20 kHz
                const double s = 1e-3 * unit(rng) * std::pow(10.0, -4.0 * std::abs(unit(rng)));
                const double b = 1e-3 * unit(rng) * std::pow(10.0, -4.0 * std::abs(unit(rng)));
                const auto sol = solveScalarContact(law, s, b, k);
                REQUIRE(std::isfinite(sol.r));
                // Converged: a residual at rounding level, or (where phi is very steep) the root
                // bracketed within a few ulps of r: phi changes sign across [r - d, r + d].
                auto phi = [&](double r) { return r + k * chordSlope(law, s, r).value - b; };
                const double scale = std::abs(sol.r) + std::abs(b) + std::abs(k * sol.slope);
                const double d = 8.0 * std::numeric_limits<double>::epsilon() * (std::abs(sol.r) + std::abs(b));
                const bool bracketed = phi(sol.r - d) <= 0.0 && phi(sol.r + d) >= 0.0;
                const double residual = bracketed ? 0.0 : std::abs(phi(sol.r)) / scale;
                worstResidual = std::max(worstResidual, residual);
                most = std::max(most, sol.iterations);
                ++solves;
                // The root's power handed to the solve two steps later (formed from D or from the
                // solve's last pow by a series): p^alpha as pow gives it.
                if (sol.penetration.xAlpha > 0.0)
                {
                    ++powers;
                    REQUIRE(sol.penetration.x == s - sol.r);
                    REQUIRE(sol.penetration.invX == Approx(1.0 / sol.penetration.x).epsilon(1e-15));
                    const double exact = std::pow(sol.penetration.x, alpha);
                    worstPower = std::max(worstPower, std::abs(sol.penetration.xAlpha - exact) / exact);
                }
            }
    INFO(solves << " solves, most iterations " << most << ", worst relative residual " << worstResidual << "; "
                << powers << " root powers, worst relative error " << worstPower);
    CHECK(worstResidual < 1e-13);
    CHECK(most < 200);
    CHECK(powers > 1000);
    CHECK(worstPower < 1e-13);
}

TEST_CASE("a scalar solve started from a nearby equation's root (NearbyRoot) finds the cold solve's root to "
          "rounding in one evaluation")
{
    // SharedBody's trials: the same point and s, b moved by the bridge's next displacement (relative
    // 1e-9 to 1e-5 of the penetration), started at the last root moved along its slope.
    std::mt19937 rng(29);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    long solves = 0, coldEvaluations = 0, nearEvaluations = 0;
    double worst = 0.0;
    for (double alpha : {1.0, 1.5, 2.0, 3.0})
        for (int i = 0; i < 2000; ++i)
        {
            const ContactLaw law{std::pow(10.0, 8.0 + 4.0 * std::abs(unit(rng))), alpha};
            const double k = std::pow(10.0, -9.0 + 2.0 * unit(rng));
            const double s = 1e-6 * std::abs(unit(rng));
            const double b = s - 2e-6 * std::abs(unit(rng));  // pressing at n+1
            const auto first = solveScalarContact(law, s, b, k);
            if (first.slope == 0.0 || !(first.r < s))
                continue;
            const double move = (s - first.r) * std::pow(10.0, -9.0 + 4.0 * std::abs(unit(rng))) * unit(rng);
            const double drdb = 1.0 / (1.0 + k * chordSlopeDerivative(law, s, first));
            const NearbyRoot nearby{first.r + move * drdb, first.penetration};
            const auto cold = solveScalarContact(law, s, b + move, k);
            const auto warm = solveScalarContact(law, s, b + move, k, nullptr, nullptr, &nearby);
            worst = std::max(worst, std::abs(warm.r - cold.r) / (std::abs(cold.r) + (s - cold.r)));
            REQUIRE(warm.slope == Approx(cold.slope).epsilon(1e-12));
            coldEvaluations += cold.iterations;
            nearEvaluations += warm.iterations;
            ++solves;
        }
    INFO(solves << " solves: " << coldEvaluations << " iterations cold, " << nearEvaluations << " from nearby; the "
                << "largest difference in r " << worst << " of |r| + p");
    CHECK(solves > 4000);
    CHECK(worst < 1e-14);
    CHECK(nearEvaluations <= solves + solves / 100);  // one evaluation, but for one in a hundred
    CHECK(nearEvaluations < coldEvaluations);
}

TEST_CASE("the coupled P x P contact solve converges on a dense coupling")
{
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    const int P = 6;
    int most = 0;
    for (int trial = 0; trial < 200; ++trial)
    {
        DenseCoupling c(P, rng);
        REQUIRE_FALSE(c.system.isDiagonal());
        std::vector<double> s(P), b(P), r(P), G(P);
        for (int j = 0; j < P; ++j)
        {
            s[j] = 1e-5 * unit(rng);
            b[j] = 1e-5 * unit(rng);
        }
        most = std::max(most, c.system.solve(s.data(), b.data(), r.data(), G.data()));
        INFO("trial " << trial);
        CHECK(c.relativeResidual(r, Eigen::Map<Eigen::VectorXd>(G.data(), P), b) <= 1e-12);
    }
    INFO("most Newton iterations " << most);
    CHECK(most <= 100);
}

TEST_CASE("the coupled solve with one point touching is exact whether or not its force pushes others on")
{
    // One point touches (at n-1 or with the contact-free prediction); the others start off the
    // obstacle. Its force moves them through the coupling: where they stay off, the solve takes the
    // one-point path; where they are pushed on, the coupled Newton. Either way r and every G(r),
    // recomputed here from the law, solve r + A G(r) = b.
    std::mt19937 rng(17);
    const int P = 5;
    int othersStayedOff = 0, othersPushedOn = 0;
    for (int trial = 0; trial < 400; ++trial)
    {
        DenseCoupling c(P, rng);
        REQUIRE_FALSE(c.system.isDiagonal());
        const int a = trial % P;
        std::vector<double> s(P), b(P), r(P), G(P);
        onePointTouching(a, rng, s, b);
        c.system.solve(s.data(), b.data(), r.data(), G.data());
        Eigen::VectorXd Gv(P);
        int on = 0;
        for (int j = 0; j < P; ++j)
        {
            Gv[j] = chordSlope(c.points[size_t(j)].law, s[size_t(j)], r[size_t(j)]).value;
            CHECK(G[size_t(j)] == Approx(Gv[j]).epsilon(1e-12).margin(1e-300));
            on += j != a && Gv[j] != 0.0;
        }
        (on > 0 ? othersPushedOn : othersStayedOff) += 1;
        INFO("trial " << trial);
        CHECK(c.relativeResidual(r, Gv, b) <= 1e-12);
    }
    INFO(othersStayedOff << " trials with the others off, " << othersPushedOn << " with some pushed on");
    CHECK(othersStayedOff > 50);
    CHECK(othersPushedOn > 50);
}

TEST_CASE("a solve takes a trial of one point alone only where it poses that very equation, and then gives the "
          "same bits")
{
    // ContactSystem::solveAlone keeps its solution for the next solve, which takes it where that point
    // presses alone with the same s, b and known powers. Against a copy of the system given no trial,
    // and one given a trial with b moved by 1e-9 of itself (which must not be taken: the solve starts
    // from its root, within the step, and finds the same root to rounding; after beginStep() it is
    // forgotten, and the solve gives the fresh one's bits).
    std::mt19937 rng(23);
    const int P = 5;
    int taken = 0;
    double worstMoved = 0.0;
    for (int n = 0; n < 400; ++n)
    {
        DenseCoupling c(P, rng);
        const int a = n % P;
        std::vector<double> s(P), b(P);
        onePointTouching(a, rng, s, b);
        ContactSystem fresh = c.system, moved = c.system, forgotten = c.system;
        auto solved = [&](ContactSystem& system) {
            std::vector<double> r(P), G(P);
            system.solve(s.data(), b.data(), r.data(), G.data());
            r.insert(r.end(), G.begin(), G.end());
            return r;
        };
        c.system.solveAlone(a, s[size_t(a)], b[size_t(a)]);
        moved.solveAlone(a, s[size_t(a)], b[size_t(a)] * (1.0 + 1e-9));
        forgotten.solveAlone(a, s[size_t(a)], b[size_t(a)] * (1.0 + 1e-9));
        forgotten.beginStep();
        const auto withTrial = solved(c.system), without = solved(fresh), withMoved = solved(moved);
        const auto afterStep = solved(forgotten);
        INFO("system " << n);
        CHECK(std::memcmp(withTrial.data(), without.data(), without.size() * sizeof(double)) == 0);
        CHECK(std::memcmp(afterStep.data(), without.data(), without.size() * sizeof(double)) == 0);
        for (int j = 0; j < P; ++j)  // r to rounding of its scale (|r| + |s|), G to rounding of its own
        {
            const double scale = std::abs(without[size_t(j)]) + std::abs(s[size_t(j)]);
            worstMoved = std::max(worstMoved, std::abs(withMoved[size_t(j)] - without[size_t(j)]) / scale);
            const double G = without[size_t(P + j)], movedG = withMoved[size_t(P + j)];
            worstMoved = std::max(worstMoved, G == 0.0 ? std::abs(movedG) : std::abs(movedG - G) / std::abs(G));
        }
        CHECK_FALSE(moved.tookTrial());
        CHECK_FALSE(forgotten.tookTrial());
        CHECK_FALSE(fresh.tookTrial());
        taken += c.system.tookTrial();
        // Good for one solve: the next, posed the same, solves.
        solved(c.system);
        CHECK_FALSE(c.system.tookTrial());
    }
    INFO(taken << " of 400 solves took the trial; a moved trial's start moved the solution by " << worstMoved);
    CHECK(taken > 100);
    CHECK(worstMoved < 1e-13);
}

TEST_CASE("the lanes' contact solve gives each lane the scalar solve's solution to rounding")
{
    // Random equations over the laws and scales of the test above, in batches of every size, with
    // known powers near s (as a string's solve two steps later has them), far from it, or none.
    std::mt19937 rng(23);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    long lanes = 0, inContact = 0, differing = 0;
    double worst = 0.0;
    for (double alpha : {1.0, 1.3, 2.0, 3.5})
    {
        const DividedSeries series = dividedSeries(alpha);
        for (int batchIndex = 0; batchIndex < 3000; ++batchIndex)
        {
            ContactLaneBatch batch;
            batch.exponent = alpha;
            batch.series = &series;
            std::vector<ScalarContactRequest> requests;
            const int count = 1 + batchIndex % kContactLanes;
            for (int i = 0; i < count; ++i)
            {
                ScalarContactRequest q;
                q.law = {std::pow(10.0, 8.0 + 8.0 * std::abs(unit(rng))), alpha};
                q.k = std::pow(10.0, -12.0 + 4.0 * unit(rng));
                q.s = 1e-3 * unit(rng) * std::pow(10.0, -4.0 * std::abs(unit(rng)));
                q.b = 1e-3 * unit(rng) * std::pow(10.0, -4.0 * std::abs(unit(rng)));
                q.series = &series;
                const double x = q.s * (1.0 + (i % 3 == 0 ? 1e-8 : 0.3) * unit(rng));
                if (i % 3 != 2 && x > 0.0)
                    q.known = {x, std::pow(x, alpha), 1.0 / x};
                requests.push_back(q);
                batch.add(q);
            }
            solveContactLanes(batch);
            for (int i = 0; i < count; ++i)
            {
                const auto scalar = solveScalarContact(requests[size_t(i)]);
                const auto& lane = batch.solution[i];
                ++lanes;
                inContact += scalar.iterations > 0 ? 1 : 0;
                REQUIRE(lane.iterations == scalar.iterations);
                const double scale = std::abs(scalar.r) + std::abs(requests[size_t(i)].b);
                worst = std::max(worst, std::abs(lane.r - scalar.r) / scale);
                worst = std::max(worst, std::abs(lane.slope - scalar.slope) / (std::abs(scalar.slope) + 1e-300));
                worst = std::max(worst, std::abs(lane.penetration.xAlpha - scalar.penetration.xAlpha)
                                            / (std::abs(scalar.penetration.xAlpha) + 1e-300));
                differing += lane.r != scalar.r || lane.slope != scalar.slope
                                     || lane.penetration.xAlpha != scalar.penetration.xAlpha
                                 ? 1
                                 : 0;
            }
        }
    }
    INFO(lanes << " lanes, " << inContact << " iterated, " << differing << " not bit for bit, worst relative "
               << worst);
    // The same operations lane by lane; GCC fuses a few multiply-adds differently in the vector code,
    // so a solution may differ from the scalar one in its last bits (measured: 1.1e-13 at worst).
    CHECK(inContact > lanes / 4);
    CHECK(worst <= 1e-12);
}

TEST_CASE("the quadratic spline's force stays within its tolerance of K eta^alpha and its solve is exact for it")
{
    std::mt19937 rng(31);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    for (double alpha : {1.0, 1.3, 1.5, 2.0, 3.0})
        for (double K : {1e7, 1e10, 1e13})
        {
            const ContactSpline spline({K, alpha});
            // The force over the stated range, on a fine log grid (between the knots too).
            double worstForce = 0.0;
            for (int i = 0; i <= 6000; ++i)
            {
                const double eta = ContactSpline::kLowest * std::pow(10.0, 6.0 * i / 6000.0);
                worstForce = std::max(worstForce, std::abs(spline.force(eta) / (K * std::pow(eta, alpha)) - 1.0));
            }
            // Random equations: the solution is the root of the spline's own equation (its chord
            // slope), and near the exact law's root.
            double worstResidual = 0.0;
            int most = 0;
            for (int n = 0; n < 2000; ++n)
            {
                const double k = std::pow(10.0, -12.0 + 2.0 * unit(rng)) * 1e13 / K;
                const double s = 1e-5 * unit(rng) * std::pow(10.0, -2.0 * std::abs(unit(rng)));
                const double b = 1e-5 * unit(rng) * std::pow(10.0, -2.0 * std::abs(unit(rng)));
                const auto sol = spline.solve(s, b, k);
                REQUIRE(std::isfinite(sol.r));
                const double r = sol.r;
                const double G = r != 0.0 ? (spline.potential(s - r) - spline.potential(s)) / r : sol.slope;
                const double scale = std::abs(r) + std::abs(b) + std::abs(k * G);
                worstResidual = std::max(worstResidual, std::abs(r + k * sol.slope - b) / scale);
                if (std::abs(r) > 1e-9 * scale)
                    REQUIRE(sol.slope == Approx(G).epsilon(1e-9).margin(1e-12 * std::abs(sol.slope) + 1e-300));
                most = std::max(most, sol.iterations);
            }
            INFO("alpha " << alpha << ", K " << K << ": " << spline.knotCount() << " knots, worst force error "
                          << worstForce << ", worst residual " << worstResidual << ", most bisection steps " << most);
            CHECK(worstForce <= ContactSpline::kTolerance);
            if (alpha > 1.0)
                CHECK(worstForce > 0.5 * ContactSpline::kTolerance);  // the knots are as sparse as allowed
            CHECK(worstResidual < 1e-12);
            CHECK(most <= 8);
        }
    // The plugin's steepest law is rebuilt within the reserved capacity (setLaw does not allocate).
    CHECK(ContactSpline({1e13, 4.0}).knotCount() <= ContactSpline::kReservedKnots);
}

TEST_CASE("chordSlopeDerivative at a scalar solve's root is the chord slope's centred difference, for a point's "
          "law and a spring's")
{
    // The body's secant takes a trial's dF/dW from it (ModalSolver::trialOnMovingBridge). A spring's
    // derivative is the constant K/2 + R/(2 dt) at every r, whether or not the solution carries it.
    ContactLaw spring;
    spring.bilateral = true;
    spring.exponent = 1.0;
    spring.stiffness = 1e8;
    spring.damping = 1e3;
    spring = solverLaw(spring, 1e-6);
    std::mt19937 rng(41);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    for (const ContactLaw& law : {ContactLaw{1e10, 1.5}, ContactLaw{1e12, 1.0}, spring})
    {
        double worst = 0.0;
        int compared = 0;
        for (int n = 0; n < 2000; ++n)
        {
            const double k = std::pow(10.0, -13.0 + 2.0 * unit(rng));
            const double s = 1e-5 * unit(rng) * std::pow(10.0, -2.0 * std::abs(unit(rng)));
            const double b = 1e-5 * unit(rng) * std::pow(10.0, -2.0 * std::abs(unit(rng)));
            ScalarContactSolution sol = solveScalarContact(law, s, b, k);
            sol.slopeDerivative = std::numeric_limits<double>::quiet_NaN();  // from the root alone
            const double h = 1e-6 * std::abs(sol.r);
            if (!(h > 1e-13) || (!law.bilateral && sol.slope == 0.0))
                continue;  // a root at r ~ 0, or off the obstacle at both ends (G = 0 around it)
            const double difference =
                (chordSlope(law, s, sol.r + h).value - chordSlope(law, s, sol.r - h).value) / (2.0 * h);
            const double scale = std::abs(difference) + std::abs(sol.slope / sol.r);
            worst = std::max(worst, std::abs(chordSlopeDerivative(law, s, sol) - difference) / scale);
            ++compared;
        }
        INFO((law.bilateral ? "spring" : "point") << ", exponent " << law.exponent << ": " << compared
                                                  << " roots compared, worst relative error " << worst);
        CHECK(compared > 500);
        CHECK(worst < 1e-4);
    }
    CHECK(chordSlopeDerivative(spring, 1e-6, ScalarContactSolution{}) == Approx(0.5 * 1e8 + 1e3 / 2e-6));
}

TEST_CASE("the quadratic spline's solve gives G'(r) at its root, as the chord slope's own difference quotient")
{
    // G(r) = (psi(s - r) - psi(s)) / r; its derivative at the root (ScalarContactSolution::
    // slopeDerivative) against a centred difference over +-1e-6 of r. The body's Newton step on the
    // bridge (SharedBody) takes it.
    std::mt19937 rng(37);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    for (double alpha : {1.0, 1.5, 3.0})
    {
        const ContactSpline spline({1e11, alpha});
        auto G = [&](double s, double r) { return (spline.potential(s - r) - spline.potential(s)) / r; };
        double worst = 0.0;
        int compared = 0;
        for (int n = 0; n < 3000; ++n)
        {
            const double k = std::pow(10.0, -12.0 + 2.0 * unit(rng)) * 1e13 / 1e11;
            const double s = 1e-5 * unit(rng) * std::pow(10.0, -2.0 * std::abs(unit(rng)));
            const double b = 1e-5 * unit(rng) * std::pow(10.0, -2.0 * std::abs(unit(rng)));
            const auto sol = spline.solve(s, b, k);
            REQUIRE(std::isfinite(sol.slopeDerivative));
            const double h = 1e-6 * std::abs(sol.r);
            if (!(h > 1e-13))
                continue;  // a root at r ~ 0: the quotient has nothing to difference
            const double difference = (G(s, sol.r + h) - G(s, sol.r - h)) / (2.0 * h);
            const double scale = std::abs(difference) + std::abs(sol.slope / sol.r);
            worst = std::max(worst, std::abs(sol.slopeDerivative - difference) / scale);
            ++compared;
        }
        INFO("alpha " << alpha << ": " << compared << " roots compared, worst relative error " << worst);
        CHECK(compared > 1000);
        CHECK(worst < 1e-4);
    }
}

TEST_CASE("a spring and a point that can touch: the trial with the spring is the coupled solve, and its dG/db "
          "matches a difference")
{
    // Point 0 a damped spring (a bilateral law), point 1 a stiff unilateral one, coupled densely.
    // ContactSystem::trialWithSpring poses solveWithBilateral's Schur complement without keeping
    // anything: its G_t and G_a are the solve's, and its derivatives (both b raised together, as a
    // bridge that sinks) those of a centred difference over +-1e-7 of the b's scale.
    std::mt19937 rng(41);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    double worstForce = 0.0, worstSlope = 0.0;
    int touching = 0, compared = 0;
    for (int n = 0; n < 400; ++n)
    {
        DenseCoupling c(2, rng);
        c.points[0].law = solverLaw({1e8 * (1.5 + unit(rng)), 1.0, true, 10.0 * (1.0 + unit(rng))}, 1e-6);
        c.system.prepare(c.points, c.A);
        const double s[2] = {1e-6 * unit(rng), 1e-5 * unit(rng)};
        const double b[2] = {s[0] + 1e-6 * unit(rng), s[1] - 1e-5 * unit(rng)};
        double r[2], G[2];
        c.system.solve(s, b, r, G);
        const auto trial = c.system.trialWithSpring(0, 1, s[0], b[0], s[1], b[1]);
        const double scale = std::abs(G[0]) + std::abs(G[1]) + 1e-300;
        worstForce = std::max({worstForce, std::abs(trial.Gt - G[0]) / scale, std::abs(trial.Ga - G[1]) / scale});
        touching += G[1] != 0.0;
        const double h = 1e-7 * (std::abs(b[1]) + std::abs(b[0]));
        const auto up = c.system.trialWithSpring(0, 1, s[0], b[0] + h, s[1], b[1] + h);
        const auto down = c.system.trialWithSpring(0, 1, s[0], b[0] - h, s[1], b[1] - h);
        if ((up.Ga == 0.0) != (down.Ga == 0.0))
            continue;  // the point lifts off within the difference: G_a has a kink there
        const double dGt = (up.Gt - down.Gt) / (2.0 * h), dGa = (up.Ga - down.Ga) / (2.0 * h);
        const double slopeScale = std::abs(dGt) + std::abs(dGa);
        worstSlope =
            std::max({worstSlope, std::abs(trial.dGt - dGt) / slopeScale, std::abs(trial.dGa - dGa) / slopeScale});
        ++compared;
    }
    INFO(touching << " of 400 with the point pressing, " << compared << " derivatives compared; worst G " << worstForce
                  << ", worst dG/db " << worstSlope);
    CHECK(touching > 100);
    CHECK(touching < 380);
    CHECK(compared > 350);
    CHECK(worstForce < 1e-12);
    CHECK(worstSlope < 1e-5);
}
