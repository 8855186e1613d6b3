// Strings in their own solvers on one shared body (SharedBody.h, LinearStringBank.h): as the one joined
// solver moves them, the bank, and the force slope the body's secant takes.

#include "TestSupport.h"

#include "offline/OfflineRender.h"
#include "offline/Scene.h"
#include "physics/body/FactoryBodies.h"
#include "physics/body/ModalBody.h"
#include "physics/body/SharedBody.h"
#include "physics/string/StringDiscretisation.h"
#include "realtime/sympathetic/SympatheticStrings.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <complex>
#include <numbers>

using namespace jawari;

namespace
{
// Two scenes' strings and bridges on the tanpura body, M modes each at 192 kHz: in one joined solver
// and each in its own solver on a SharedBody, 7000 steps (36 ms, both strings on and off their
// bridges many times). The largest difference of the first string's pickup, relative to its peak.
struct SharedAgainstJoined
{
    double largest = 0.0, bridge = 0.0;
    int pressingSteps = 0, mostEvaluations = 0;
    long evaluations = 0;  // contact solves in all
    long jawariSteps = 0;  // steps of a sympathetic string pressing its jawari (summed over them)
    // Steps whose last solve took the step's last trial (ModalSolver::lastSolveWasTrial), summed over
    // the played strings and over the sympathetic ones.
    long playedSolvesByTrial = 0, sympatheticSolvesByTrial = 0;
    bool banked = false;       // the sympathetic strings stepped as a bank
    double tarafEnergy = 0.0;  // their string energy at the end (J), from their solvers
};

// What a sympathetic string stands on: its bridge's spring; that and its jawari; or two springs (a
// scene's string held at two points, whose force no trial poses).
enum class TarafPoints
{
    spring,
    springAndJawari,
    twoSprings
};

// `count` sympathetic strings tuned to Kafi from 200 Hz, M modes, on `points`; their points out of
// reach left out or not.
std::vector<ModalSolverConfig> sympatheticConfigs(int count, int M, double rate, TarafPoints points, bool reach)
{
    std::vector<ModalSolverConfig> configs;
    for (int k = 0; k < count; ++k)
    {
        const auto string = sympatheticStringAt(200.0 * std::pow(2.0, sympatheticSemitones(k, SympatheticScale::kafi) / 12.0));
        std::vector<Obstacle> bridge = {sympatheticBridge(string.lengthMetres)};
        if (points == TarafPoints::springAndJawari)
            bridge.push_back(sympatheticJawari(string.lengthMetres));
        if (points == TarafPoints::twoSprings)
        {
            bridge.push_back(bridge.front());
            bridge.back().position = sympatheticJawari(string.lengthMetres).position;
        }
        configs.push_back(
            stringSolverConfig(string, bridge, M, rate, 0.9 * string.lengthMetres, PickupQuantity::displacement));
        configs.back().leaveOutOfReach = reach;
    }
    return configs;
}

// `tarafModes`: the sympathetic strings' modes (0: M). `banked`: they step as one LinearStringBank
// (SharedBody::bankLinear), taken from their solvers and given back every 96 steps, as the instrument
// does around each chunk.
SharedAgainstJoined sharedAgainstJoined(const Scene& sa, const Scene& pa, int M, int sympathetic = 0, int steps = 7000,
                                        TarafPoints points = TarafPoints::spring, bool reach = false,
                                        int tarafModes = 0, bool banked = false)
{
    const int tarafM = tarafModes > 0 ? tarafModes : M;
    const double rate = 192000.0;
    auto configOf = [&](const Scene& s) {
        auto c = stringSolverConfig(s.string, s.obstacles, M, rate, s.pickup.position, PickupQuantity::displacement);
        c.leaveOutOfReach = false;
        return c;
    };
    const auto first = configOf(sa), second = configOf(pa);
    const auto pluckOf = [&](const Scene& s) {
        return pluckModalShape(s.string.lengthMetres, M, s.excitation.position, s.excitation.amplitude);
    };
    const ModalBody body = *factoryBody("tanpura");

    const auto linear = sympatheticConfigs(sympathetic, tarafM, rate, points, false);  // at rest, after the two
    auto joinedConfig = first;
    auto quiet = second;
    quiet.pickupWeights.clear();
    appendString(joinedConfig, quiet);
    for (auto other : linear)
    {
        other.pickupWeights.clear();
        appendString(joinedConfig, other);
    }
    joinedConfig = withBody(joinedConfig, {&body, std::vector<char>(joinedConfig.contacts.size(), 1), 1.0});
    ModalSolver joined(joinedConfig);
    auto initial = pluckOf(sa);
    for (const double q : pluckOf(pa))
        initial.push_back(std::sqrt(pa.string.linearDensity / sa.string.linearDensity) * q);
    initial.resize(size_t(joinedConfig.modes.size()), 0.0);
    joined.setInitialDisplacement(initial);

    ModalSolver a(first), b(second);
    a.setInitialDisplacement(pluckOf(sa));
    b.setInitialDisplacement(pluckOf(pa));
    SharedBody shared(body, 1.0, a.timeStep());
    shared.check(a);
    shared.check(b);
    const auto tarafConfigs = sympatheticConfigs(sympathetic, tarafM, rate, points, reach);
    std::vector<ModalSolver> tarafs(tarafConfigs.begin(), tarafConfigs.end());
    std::vector<ModalSolver*> strings = {&a, &b};
    for (auto& t : tarafs)
    {
        if (points == TarafPoints::springAndJawari)
            shared.check(t);
        else
            shared.checkLinear(t);
        strings.push_back(&t);
    }
    SharedAgainstJoined result;
    double peak = 0.0;
    for (int n = 0; n < steps; ++n)
    {
        if (banked && n % 96 == 0)
        {
            shared.unbankLinear(strings.data());
            result.banked = shared.bankLinear(strings.data(), 2, int(strings.size()));
        }
        joined.step();
        shared.step(strings.data(), int(strings.size()), 2);
        peak = std::max(peak, std::abs(joined.pickup()));
        result.largest = std::max(result.largest, std::abs(joined.pickup() - a.pickup()));
        result.bridge = std::max(result.bridge, std::abs(shared.bridgeDisplacement()));
        result.pressingSteps += shared.lastBridgeForce() != 0.0;
        result.mostEvaluations = std::max(result.mostEvaluations, shared.lastEvaluations());
        result.evaluations += shared.lastEvaluations();
        result.playedSolvesByTrial += a.lastSolveWasTrial() + b.lastSolveWasTrial();
        for (const auto& t : tarafs)
        {
            result.jawariSteps += t.contactCount() > 1 && t.contactForce(1) != 0.0;
            result.sympatheticSolvesByTrial += t.lastSolveWasTrial();
        }
    }
    shared.unbankLinear(strings.data());
    result.largest /= peak;
    for (auto& t : tarafs)  // given back: each string's state its own solver's again
        result.tarafEnergy += t.stringEnergy();
    return result;
}
}  // namespace

TEST_CASE("Strings in their own solvers on a shared body (SharedBody) move as in the one joined solver, to "
          "rounding",
          "[body]")
{
    // Point bridges (tanpura-sa and tanpura-pa), and a 23-point bridge beside a point (sitar-bridge and
    // tanpura-pa). A grazing contact is sensitive: rounding's differences grow (tanpura-sa and -pa:
    // with one body mode 1e-16 m by step 7442, 1e-14 m by 8153, 2.6e-8 m by 20000; with the whole
    // body 2.6e-7 m by 20000; 2.4e-12 m uncoupled), so 7000 steps.
    const Scene pa = test::scene("tanpura-pa.json");
    for (const char* name : {"tanpura-sa.json", "sitar-bridge.json"})
    {
        const auto r = sharedAgainstJoined(test::scene(name), pa, 150);
        INFO(name << " beside tanpura-pa: largest difference " << r.largest << " of the pickup's peak; the bridge "
                  << "moved up to " << r.bridge << " m; " << r.pressingSteps << " steps pressing; at most "
                  << r.mostEvaluations << " contact solves in a step, " << r.evaluations << " in all");
        CHECK(r.pressingSteps > 100);
        CHECK(r.bridge > 1e-9);
        CHECK(r.largest < 1e-9);
        CHECK(r.mostEvaluations <= 8);
        // The trials find the bridge, and one round of solves confirms it: 1.00 a step on tanpura-sa,
        // 1.04 on sitar-bridge, where the secant on solves alone took 2.93 and 3.38 solves a step.
        CHECK(r.evaluations < 1.1 * 7000);
    }
    // With three sympathetic strings after them, whose force the secant takes from its affine fit.
    // They couple the two more strongly, and rounding's differences grow faster: 6e-15 of the peak by
    // step 500, about 2e-11 by 4000, 2.2e-8 by 6500. So 4000 steps.
    const auto r = sharedAgainstJoined(test::scene("sitar-bridge.json"), pa, 150, 3, 4000);
    INFO("sitar-bridge beside tanpura-pa and three sympathetic strings: largest difference " << r.largest
                                                                                           << " of the pickup's peak");
    CHECK(r.largest < 1e-9);
    // The same sympathetic strings on their jawari: no longer linear, they are solved with the played
    // strings at every evaluation (their trials the spring and the jawari together).
    const auto j =
        sharedAgainstJoined(test::scene("sitar-bridge.json"), pa, 150, 3, 4000, TarafPoints::springAndJawari);
    INFO("the same on their jawari: largest difference " << j.largest << " of the pickup's peak, " << j.jawariSteps
                                                         << " steps of a string on its jawari, " << j.evaluations
                                                         << " contact solves in 4000 steps");
    CHECK(j.jawariSteps > 1000);
    CHECK(j.largest < 1e-9);
    CHECK(j.evaluations < 1.6 * 4000);
    // Each of them takes its last trial, the Schur complement of its spring and its jawari, as its
    // solve (ModalSolver::trialWithSpring) in most steps.
    INFO(j.sympatheticSolvesByTrial << " of " << 3 * 4000 << " sympathetic strings' steps solved by their trial, "
                                    << j.playedSolvesByTrial << " of " << 2 * 4000 << " played strings' steps");
    CHECK(j.sympatheticSolvesByTrial > 0.9 * 3 * 4000);
    // The played strings likewise, where the step's last solve is at its last trial's bridge: tanpura-pa's
    // one point, and sitar-bridge's 23 points where the point its trial posed presses alone
    // (ContactSystem::solveAlone).
    CHECK(j.playedSolvesByTrial > 0.7 * 2 * 4000);
    // The same with their points out of reach left out (ContactReach), as the plugin runs them: a
    // jawari at the string's rest height is always within reach, so the reach's bookkeeping must leave
    // the motion the joined solver's.
    const auto reached =
        sharedAgainstJoined(test::scene("sitar-bridge.json"), pa, 150, 3, 4000, TarafPoints::springAndJawari, true);
    INFO("with their points out of reach left out: largest difference " << reached.largest << ", "
                                                                        << reached.jawariSteps << " steps on a jawari");
    CHECK(reached.jawariSteps == j.jawariSteps);
    CHECK(reached.largest < 1e-9);
}

TEST_CASE("Sympathetic strings stepped as one bank (LinearStringBank) move as in the joined solver, to rounding",
          "[body][sympathetic]")
{
    // Thirteen of them at the instrument's 16 modes beside sitar-bridge and tanpura-pa, taken into the
    // bank and given back every 96 steps (the instrument's chunk at 3x), against the joined solver and
    // against the same strings each in its own solver. 4000 steps, as the test above.
    const Scene pa = test::scene("tanpura-pa.json");
    const auto own =
        sharedAgainstJoined(test::scene("sitar-bridge.json"), pa, 150, 13, 4000, TarafPoints::spring, false, 16, false);
    const auto bank =
        sharedAgainstJoined(test::scene("sitar-bridge.json"), pa, 150, 13, 4000, TarafPoints::spring, false, 16, true);
    INFO("each in its own solver: largest difference " << own.largest << " of the pickup's peak; as a bank "
                                                       << bank.largest << "; their energy at the end "
                                                       << own.tarafEnergy << " J and " << bank.tarafEnergy << " J");
    CHECK(bank.banked);
    CHECK(own.largest < 1e-9);
    CHECK(bank.largest < 1e-9);
    CHECK(bank.tarafEnergy > 0.0);
    CHECK(std::abs(bank.tarafEnergy - own.tarafEnergy) < 1e-6 * own.tarafEnergy);
}

TEST_CASE("A solve's force slope on a moving bridge (solvedForceSlope) is the force's derivative there, with one "
          "point pressing and with several",
          "[body]")
{
    // sitar-bridge's 23 points plucked, on a bridge held still: at each step, the slope of the solve
    // against the centred difference of solves with the bridge 1 pm up and down (the same points
    // pressing in all three). The body's secant takes its Newton steps from this slope. Plucked harder
    // than the scene, so that more steps press at two points or more.
    constexpr double kLouder = 4.0;
    const Scene s = test::scene("sitar-bridge.json");
    const int M = 150;
    auto config =
        stringSolverConfig(s.string, s.obstacles, M, 192000.0, s.pickup.position, PickupQuantity::displacement);
    config.leaveOutOfReach = false;
    ModalSolver string(config);
    string.setInitialDisplacement(
        pluckModalShape(s.string.lengthMetres, M, s.excitation.position, kLouder * s.excitation.amplitude));
    auto pressing = [&] {
        int count = 0;
        for (int j = 0; j < string.contactCount(); ++j)
            count += string.contactForce(j) != 0.0;
        return count;
    };
    constexpr double h = 1e-12;  // m: the difference is off by about 2e-6 here where a point grazes, 2e-4 at 1e-11
    int compared[2] = {}, mostPressing = 0;
    double worst[2] = {};
    for (int n = 0; n < 6000; ++n)
    {
        string.predictOnMovingBridge();
        string.solveOnMovingBridge(0.0, 0.0);
        const int here = pressing();
        const double slope = string.solvedForceSlope();
        const double up = string.solveOnMovingBridge(0.0, h);
        const int upPressing = pressing();
        const double down = string.solveOnMovingBridge(0.0, -h);
        if (here > 0 && here == upPressing && here == pressing())
        {
            const double difference = (up - down) / (2.0 * h);
            const int k = here > 1 ? 1 : 0;
            worst[k] = std::max(worst[k], std::abs(slope - difference) / std::abs(difference));
            ++compared[k];
            mostPressing = std::max(mostPressing, here);
        }
        string.solveOnMovingBridge(0.0, 0.0);
        string.finishOnMovingBridge();
    }
    INFO("one point pressing: " << compared[0] << " steps, the slope within " << worst[0]
                                << " of the difference; several (up to " << mostPressing << "): " << compared[1]
                                << " steps, within " << worst[1]);
    CHECK(compared[0] > 100);
    CHECK(compared[1] > 100);
    CHECK(worst[0] < 1e-5);
    CHECK(worst[1] < 1e-5);
}

TEST_CASE("A string on two springs has no trial on a moving bridge; on the shared body it moves as when joined",
          "[body]")
{
    // At rest a spring's force is 0 but its slope is not: a trial that answered 0 there would give the
    // affine fit no slope, and the first step that moves the body would miss the string's stiffness.
    auto configs = sympatheticConfigs(1, 40, 192000.0, TarafPoints::twoSprings, false);
    ModalSolver held(configs.front());
    REQUIRE(held.contactCount() == 2);
    held.predictOnMovingBridge();
    double slope = 0.0;
    CHECK(std::isnan(held.trialOnMovingBridge(0.0, 1e-9, &slope)));
    auto one = sympatheticConfigs(1, 40, 192000.0, TarafPoints::spring, false);
    ModalSolver single(one.front());
    single.predictOnMovingBridge();
    const double force = single.trialOnMovingBridge(0.0, 1e-9, &slope);
    INFO("one spring: force " << force << " N at 1 nm, slope " << slope << " N/m");
    CHECK(force == Approx(slope * 1e-9).epsilon(1e-9));  // affine through 0 at rest
    CHECK(slope < -1e3);                                  // the spring pushes the rising bridge down

    const Scene pa = test::scene("tanpura-pa.json");
    const auto r = sharedAgainstJoined(test::scene("sitar-bridge.json"), pa, 150, 3, 4000, TarafPoints::twoSprings);
    INFO("three sympathetic strings on two springs each: largest difference " << r.largest << " of the pickup's peak");
    CHECK(r.largest < 1e-9);
}
