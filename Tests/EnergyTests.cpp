// The discrete energy H^{n+1/2} of docs/design.md section 2 (paper eq. 8): conserved without losses to
// the solver's tolerance, and dissipated exactly as the balance says with them.

#include "TestSupport.h"
#include "physics/modes/ModalSolver.h"
#include "physics/string/StringDiscretisation.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace jawari;

using test::losslessDrift;

TEST_CASE("lossless contact with a point obstacle conserves energy to 1e-9 over 1e5 steps, by Newton and by "
          "the quadratic spline (its own potential's energy)")
{
    for (const auto method : {ContactMethod::energyConserving, ContactMethod::quadraticSpline})
    {
        const auto s = test::paperString(DampingLaw::none);
        auto config = test::gridConfig(s, 1001, 2e6, {test::pointObstacle(0.501)});
        config.method = method;
        ModalSolver solver(config);
        solver.setInitialDisplacement(pluckModalShape(s.lengthMetres, 1001, 0.501, 1.5e-3));
        const auto d = losslessDrift(solver, 100000);
        INFO(contactMethodName(method).sceneName << ": relative drift " << d.worst << ", contact steps "
                                                 << d.contactSteps << ", peak contact energy "
                                                 << d.largestContactEnergy);
        CHECK(d.contactSteps > 10000);
        CHECK(d.largestContactEnergy > 0.0);
        CHECK(d.worst < 1e-9);
    }
}

TEST_CASE("lossless contact with a distributed bridge (DST path) conserves energy to 1e-9 over 1e5 steps")
{
    const auto s = test::paperString(DampingLaw::none);
    Obstacle bridge;
    bridge.type = ObstacleType::parabola;
    bridge.position = 0.004;
    bridge.width = 0.008;
    bridge.height = 1e-5;  // pushes 10 um into the string at its apex
    bridge.curvature = 2.0;
    bridge.law = {1e13, 1.3};
    const int M = 400;
    bridge.spacing = s.lengthMetres / (M + 1);  // sampled on the solver's own grid
    auto config = test::gridConfig(s, M, 1e6, {bridge}, ContactPath::transform);
    ModalSolver solver(config);
    REQUIRE(solver.usesTransform());
    REQUIRE(solver.contactCount() == 3);
    solver.setInitialDisplacement(pluckModalShape(s.lengthMetres, M, 0.3, 1e-3));
    const auto d = losslessDrift(solver, 100000);
    INFO("relative drift " << d.worst << ", contact steps " << d.contactSteps);
    CHECK(d.contactSteps > 1000);
    CHECK(d.worst < 1e-9);
}

TEST_CASE("lossless contact with coupled off-grid points (P x P Newton) conserves energy to 1e-9")
{
    const auto s = test::paperString(DampingLaw::none);
    const int M = 120;
    ModalSolverConfig config = test::gridConfig(s, M, 4.8e5, {});
    // Off the grid and close together, so Phi Phi^T W is dense: the coupled Newton does the work.
    for (double x : {0.1003, 0.1041, 0.1079})
        config.contacts.push_back({x, 2e-3, -2e-5, {1e11, 1.5}, -1});
    ModalSolver solver(config);
    REQUIRE_FALSE(solver.usesTransform());
    solver.setInitialDisplacement(pluckModalShape(s.lengthMetres, M, 0.2, 1.5e-3));
    const auto d = losslessDrift(solver, 100000);
    INFO("relative drift " << d.worst << ", contact steps " << d.contactSteps);
    CHECK(d.contactSteps > 1000);
    CHECK(d.worst < 1e-9);
}

TEST_CASE("with losses the energy never increases and the balance holds step by step")
{
    const auto s = test::paperString(DampingLaw::valette);
    const int M = 1001;
    auto config = test::gridConfig(s, M, 2e6, {test::pointObstacle(0.006)});
    ModalSolver solver(config);
    solver.setInitialDisplacement(pluckModalShape(s.lengthMetres, M, 0.501, 1.5e-3));
    const double H0 = solver.energy().total;
    double previousH = H0;
    double worstIncrease = 0.0, worstBalance = 0.0;
    long contactSteps = 0;
    for (int n = 0; n < 20000; ++n)
    {
        const auto qPrev = solver.modalState(true);
        const double Hbefore = solver.energy().total;
        solver.step();
        if (solver.lastMaxPenetration() > 0.0)
            ++contactSteps;
        const auto qNext = solver.modalState(false);
        const double H = solver.energy().total;
        worstIncrease = std::max(worstIncrease, (H - previousH) / H0);
        const double loss = solver.stepLoss(qNext.data(), qPrev.data());
        worstBalance = std::max(worstBalance, std::abs(H - Hbefore + loss) / H0);
        previousH = H;
    }
    INFO("largest step increase " << worstIncrease << ", worst balance error " << worstBalance << ", contact steps "
                                  << contactSteps);
    CHECK(contactSteps > 1000);
    CHECK(worstIncrease <= 1e-13);
    CHECK(worstBalance < 1e-11);
    CHECK(previousH < 0.99 * H0);
}

TEST_CASE("lossless contact with a bridge on its own contact points (off the modes' grid) conserves energy to 1e-9")
{
    // A Sitar-like bridge on its fixed contact grid (L/1002) meets a 197-mode string off its grid:
    // 20 coupled points on the paper string, solved by the P x P Newton.
    auto s = test::paperString(DampingLaw::none);
    const int M = 197;
    auto config = stringSolverConfig(s, {test::sitarLikeBridge()}, M, 288000.0, 0.992, PickupQuantity::displacement);
    REQUIRE(config.contacts.size() == 20);
    ModalSolver solver(config);
    solver.setInitialDisplacement(pluckModalShape(s.lengthMetres, M, 0.18, 1e-3));
    const auto d = losslessDrift(solver, 100000);
    INFO("relative drift " << d.worst << ", contact steps " << d.contactSteps);
    CHECK(d.contactSteps > 1000);
    CHECK(d.worst < 1e-9);
}

TEST_CASE("points out of the string's reach never touch, and leaving them out changes the motion only by rounding")
{
    // The Sitar scene's string on its bridge (23 coupled points at L/1002), with losses, at the
    // standard 197 modes and 288 kHz, with and without the points out of reach left out.
    const auto scene = test::scene("sitar-bridge.json");
    const int M = 197;
    auto config = stringSolverConfig(scene.string, scene.obstacles, M, 288000.0, scene.pickup.position,
                                     PickupQuantity::displacement);
    const int P = static_cast<int>(config.contacts.size());
    REQUIRE(P == 23);
    ModalSolver filtered(config);
    config.leaveOutOfReach = false;
    ModalSolver everyPoint(config);
    const auto pluck = pluckModalShape(scene.string.lengthMetres, M, scene.excitation.position, 1e-3);
    filtered.setInitialDisplacement(pluck);
    everyPoint.setInitialDisplacement(pluck);

    std::vector<double> shapes(size_t(P) * M);
    for (int j = 0; j < P; ++j)
        for (int p = 0; p < M; ++p)
            shapes[size_t(j) * M + p] = modeShape(scene.string.lengthMetres, p + 1, config.contacts[j].position);
    const long steps = 288000;  // 1 s
    double worstLeftOut = -1.0, difference = 0.0, norm = 0.0;
    long live = 0, leftOutChecks = 0;
    std::vector<double> u(P);
    for (long n = 0; n < steps; ++n)
    {
        filtered.step();
        everyPoint.step();
        live += filtered.livePointCount();
        difference += std::pow(filtered.pickup() - everyPoint.pickup(), 2);
        norm += std::pow(everyPoint.pickup(), 2);
        if (n % 7 == 0)
        {
            // Where the points left out are, from the whole modal state: off their obstacle.
            const auto q = filtered.modalState();
            for (int j = 0; j < P; ++j)
                if (!filtered.pointLive(j))
                {
                    double uj = 0.0;
                    for (int p = 0; p < M; ++p)
                        uj += shapes[size_t(j) * M + p] * q[size_t(p)];
                    worstLeftOut = std::max(worstLeftOut, config.contacts[j].height - uj);
                    ++leftOutChecks;
                }
        }
    }
    const double meanLive = double(live) / steps;
    const double relL2 = std::sqrt(difference / norm);
    INFO("mean live points " << meanLive << " of " << P << ", highest penetration of a point left out "
                             << worstLeftOut << " m, pickup relL2 " << relL2);
    CHECK(leftOutChecks > 1000);
    CHECK(meanLive < 0.6 * P);  // measured 12.0 of 23
    CHECK(worstLeftOut < 0.0);  // measured -5.0e-5 m
    CHECK(relL2 < 1e-12);       // measured 0: the same arithmetic on the points that touch
}

namespace
{
// Where the live points a split step left out are, from the whole modal state (`shapes`: P x M, the
// sine modes at the contact points): the highest penetration among them (< 0: all off their obstacle)
// and how many were checked.
std::pair<double, long> leftOutPenetration(ModalSolver& split, const ModalSolverConfig& config,
                                           const std::vector<double>& shapes)
{
    const auto q = split.modalState();
    const int P = static_cast<int>(config.contacts.size()), M = config.modes.size();
    double highest = -1.0;
    long checked = 0;
    for (int j = 0; j < P; ++j)
        if (split.pointLive(j) && !split.pointSolved(j))
        {
            double uj = 0.0;
            for (int p = 0; p < M; ++p)
                uj += shapes[size_t(j) * M + p] * q[size_t(p)];
            highest = std::max(highest, config.contacts[j].height - uj);
            ++checked;
        }
    return {highest, checked};
}
}  // namespace

TEST_CASE("A step over a thousand modes or more solves only the points its high modes may carry to the bridge "
          "(EngagedPoints), and its motion is the step's over every live point to rounding")
{
    // parabola-bridge as the reference's refinement study runs it, a rung down: 1201 modes at 4 MHz,
    // its bridge sampled every L/8016 (161 points), the 1.5 mm pluck, 4 ms.
    auto scene = test::scene("parabola-bridge.json");
    const double L = scene.string.lengthMetres;
    for (auto& o : scene.obstacles)
        if (o.isDistributed())
            o.spacing = L / 8016.0;
    const int M = 1201;
    auto config =
        stringSolverConfig(scene.string, scene.obstacles, M, 4e6, scene.pickup.position, PickupQuantity::displacement);
    const int P = static_cast<int>(config.contacts.size());
    REQUIRE(P == 161);
    ModalSolver split(config);
    config.splitModes = false;
    ModalSolver whole(config);
    const auto pluck = pluckModalShape(L, M, scene.excitation.position, scene.excitation.amplitude);
    split.setInitialDisplacement(pluck);
    whole.setInitialDisplacement(pluck);

    std::vector<double> shapes(size_t(P) * M);
    for (int j = 0; j < P; ++j)
        for (int p = 0; p < M; ++p)
            shapes[size_t(j) * M + p] = modeShape(L, p + 1, config.contacts[j].position);
    const long steps = 16000;
    long pressingSteps = 0, leftOutChecks = 0;
    double worstLeftOut = -1.0, difference = 0.0, norm = 0.0;
    for (long n = 0; n < steps; ++n)
    {
        split.step();
        whole.step();
        difference += std::pow(split.pickup() - whole.pickup(), 2);
        norm += std::pow(whole.pickup(), 2);
        pressingSteps += whole.lastMaxPenetration() > 0.0;
        if (n % 32 == 0)
        {
            const auto [highest, checked] = leftOutPenetration(split, config, shapes);
            worstLeftOut = std::max(worstLeftOut, highest);
            leftOutChecks += checked;
        }
    }
    const auto& counters = split.splitCounters();
    const double solvedPerStep = double(counters.engaged) / double(counters.steps);
    const double relL2 = std::sqrt(difference / norm);
    INFO("pickup relL2 " << relL2 << ", points solved per step " << solvedPerStep << " of " << P << ", engaged afresh "
                         << counters.joins << ", solved again " << counters.resolves << ", steps pressing "
                         << pressingSteps << ", highest penetration of a point left out " << worstLeftOut << " m");
    CHECK(counters.steps == steps);
    CHECK(whole.splitCounters().steps == 0);
    CHECK(pressingSteps > steps / 4);
    CHECK(relL2 < 1e-12);
    CHECK(solvedPerStep < 0.15 * P);
    CHECK(leftOutChecks > 5000);
    CHECK(worstLeftOut < 0.0);
}

namespace
{
// A bridge on [0, 8 mm] pushing 10 um into the string and DAFx-16's thread beside it at 10 mm
// (1.2 mm wide, 1.2e5 N/m, `damping` kg/s), both on the solver's own grid of M modes.
std::vector<Obstacle> bridgeAndDampedThread(double lengthMetres, int M, double damping)
{
    Obstacle bridge;
    bridge.type = ObstacleType::parabola;
    bridge.position = 0.004;
    bridge.width = 0.008;
    bridge.height = 1e-5;
    bridge.curvature = 2.0;
    bridge.law = {1e13, 1.3};
    bridge.spacing = lengthMetres / (M + 1);
    Thread thread;
    thread.model = ThreadModel::springDamper;
    thread.damping = damping;
    return {bridge, threadObstacle(thread, 0.010, 0.0, lengthMetres / (M + 1))};
}
}  // namespace

TEST_CASE("a damped thread on the reference grid: without its damper the energy is conserved to 1e-9 over 1e5 "
          "steps; with it the balance holds step by step and the damper only takes",
          "[thread]")
{
    const auto s = test::paperString(DampingLaw::none);
    const int M = 400;
    SECTION("its spring alone stores and gives back")
    {
        ModalSolver solver(test::gridConfig(s, M, 1e6, bridgeAndDampedThread(s.lengthMetres, M, 0.0)));
        REQUIRE(solver.contact(solver.contactCount() - 1).law.bilateral);
        solver.setInitialDisplacement(pluckModalShape(s.lengthMetres, M, 0.3, 1e-3));
        const auto d = losslessDrift(solver, 100000);
        INFO("relative drift " << d.worst << ", bridge contact steps " << d.contactSteps << ", largest contact energy "
                               << d.largestContactEnergy << " J");
        CHECK(d.contactSteps > 1000);
        CHECK(d.largestContactEnergy > 1e-3 * solver.energy().total);  // the thread's spring held some
        CHECK(d.worst < 1e-9);
    }
    SECTION("its damper takes exactly what the balance says, and nothing else is lost")
    {
        ModalSolver solver(test::gridConfig(s, M, 1e6, bridgeAndDampedThread(s.lengthMetres, M, 1.2)));
        solver.setInitialDisplacement(pluckModalShape(s.lengthMetres, M, 0.3, 1e-3));
        const double H0 = solver.energy().total;
        double previous = H0, worstIncrease = -1.0, worstBalance = 0.0, taken = 0.0;
        for (int n = 0; n < 20000; ++n)
        {
            solver.step();
            const double H = solver.energy().total;
            const double loss = solver.damperLoss();
            taken += loss;
            worstIncrease = std::max(worstIncrease, (H - previous) / H0);
            worstBalance = std::max(worstBalance, std::abs(H - previous + loss) / H0);
            previous = H;
        }
        INFO("the damper took " << taken / H0 << " of H0; largest step increase " << worstIncrease
                                << ", worst balance error " << worstBalance);
        CHECK(taken > 0.01 * H0);
        CHECK(worstIncrease <= 1e-13);
        CHECK(worstBalance < 1e-11);
    }
}
