// The points out of reach on a shared body (BodyReach.h): left out of the strings' solves, they
// never touch, the motion is the one with every point live, and the energy balance holds.

#include "SharedBodySupport.h"
#include "TestSupport.h"
#include "offline/Scene.h"
#include "physics/body/FactoryBodies.h"
#include "physics/body/SharedBody.h"
#include "physics/string/StringDiscretisation.h"
#include "physics/string/StringModel.h"
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <deque>
#include <string>
#include <vector>

using namespace jawari;

namespace
{
using test::scene;
using test::stringsOf;
using test::tanpuraBody;
constexpr int kModes = test::kBodyTestModes;
constexpr double kRate = test::kBodyTestRate;

// The highest of h_j + w^n - u_j^n over the points string s leaves out (from its whole modal
// state), and how many it leaves out.
std::pair<double, int> leftOut(ModalSolver& s, double bridge, double lengthMetres)
{
    double highest = -1.0;
    int count = 0;
    const auto q = s.modalState();
    for (int j = 0; j < s.contactCount(); ++j)
        if (!s.pointLive(j))
        {
            double u = 0.0;
            for (int p = 0; p < kModes; ++p)
                u += modeShape(lengthMetres, p + 1, s.contact(j).position) * q[size_t(p)];
            highest = std::max(highest, s.contact(j).height + bridge - u);
            ++count;
        }
    return {highest, count};
}
}  // namespace

TEST_CASE("On a shared body the points out of reach are left out, never touch, and change the motion only by "
          "rounding",
          "[body]")
{
    // sitar-bridge (23 points) and tanpura-pa on the tanpura body, both plucked, with losses: 0.5 s.
    const std::vector<Scene> scenes = {scene("sitar-bridge.json"), scene("tanpura-pa.json")};
    const ModalBody body = tanpuraBody(false);
    auto every = stringsOf(scenes, {true, true}, false, false);
    auto chosen = stringsOf(scenes, {true, true}, true, false);
    REQUIRE(chosen.solvers[0].leavesOutOfReach());
    SharedBody everyBody(body, 1.0, 1.0 / kRate), chosenBody(body, 1.0, 1.0 / kRate);
    // The same string alone on rigid supports, choosing its own points: how many it keeps.
    auto alone = stringsOf({scenes[0]}, {true}, true, false);
    const long steps = long(0.5 * kRate), compared = 7000;
    const int P = chosen.solvers[0].contactCount();
    double highest = -1.0, difference = 0.0, norm = 0.0;
    long live = 0, liveAlone = 0, checks = 0, resolved = 0, firstResolved = -1;
    for (long n = 0; n < steps; ++n)
    {
        everyBody.step(every.pointers.data(), 2);
        chosenBody.step(chosen.pointers.data(), 2);
        alone.solvers[0].step();
        live += chosen.solvers[0].livePointCount();
        liveAlone += alone.solvers[0].livePointCount();
        resolved += chosenBody.lastResolved();
        if (chosenBody.lastResolved() && firstResolved < 0)
            firstResolved = n;
        if (n < compared)
        {
            difference += std::pow(chosen.solvers[0].pickup() - every.solvers[0].pickup(), 2);
            norm += std::pow(every.solvers[0].pickup(), 2);
        }
        if (n % 7 == 0)
        {
            const auto [h, count] =
                leftOut(chosen.solvers[0], chosenBody.bridgeDisplacement(), scenes[0].string.lengthMetres);
            highest = std::max(highest, h);
            checks += count;
        }
    }
    const double meanLive = double(live) / double(steps), relL2 = std::sqrt(difference / norm);
    const double meanAlone = double(liveAlone) / double(steps);
    INFO("sitar-bridge on the body: mean live points " << meanLive << " of " << P << " (alone on rigid supports "
                                                       << meanAlone << "), highest penetration of a point left out "
                                                       << highest << " m, pickup relL2 " << relL2 << " over "
                                                       << compared << " steps, " << resolved
                                                       << " steps solved again, the first at " << firstResolved);
    CHECK(checks > 1000);
    CHECK(meanLive < 1.1 * meanAlone);  // measured 18.64 against 17.91 of 23 (19.99 with twice the energy)
    CHECK(highest < 0.0);               // measured -1.6e-4 m
    // Rounding: the steps solved again take their joining points' u^{n-1} from the prediction (the
    // first at step 3456), and a grazing contact lets rounding grow (BodyTests, "Strings in their
    // own solvers on a shared body"), so the first 7000 steps. Measured 0 (9.3e-12 when the first
    // came at step 89).
    CHECK(relL2 < 1e-9);
}

TEST_CASE("On a shared body with points left out the discrete energy holds to 1e-9 lossless over 1e5 steps, a "
          "string at rest woken through the body",
          "[body][energy]")
{
    // sitar-bridge plucked and a second sitar-bridge string at rest beside it: the body hands the
    // quiet string energy beyond the budget it was given, and the steps that overrun are solved again.
    const std::vector<Scene> scenes = {scene("sitar-bridge.json"), scene("sitar-bridge.json")};
    const ModalBody body = tanpuraBody(true);
    auto strings = stringsOf(scenes, {true, false}, true, true);
    SharedBody shared(body, 1.0, 1.0 / kRate);
    const double H0 = shared.energy(strings.pointers.data(), 2);
    double drift = 0.0, highest = -1.0;
    long resolved = 0, leftOutPoints = 0;
    for (long n = 0; n < 100000; ++n)
    {
        shared.step(strings.pointers.data(), 2);
        resolved += shared.lastResolved();
        leftOutPoints += strings.solvers[1].contactCount() - strings.solvers[1].livePointCount();
        drift = std::max(drift, std::abs(shared.energy(strings.pointers.data(), 2) / H0 - 1.0));
        if (n % 101 == 0)
            highest = std::max(highest, leftOut(strings.solvers[1], shared.bridgeDisplacement(),
                                                scenes[1].string.lengthMetres)
                                            .first);
    }
    INFO("relative drift " << drift << ", " << resolved << " steps solved again, the quiet string left out "
                           << leftOutPoints << " point-steps, its highest penetration of a point left out " << highest
                           << " m");
    CHECK(drift < 1e-9);               // measured 7.6e-13
    CHECK(resolved > 0);               // measured 118
    CHECK(leftOutPoints > 100000);     // measured 2.0e6 of 2.3e6
    CHECK(highest < 0.0);              // measured -3.1e-6 m
}

TEST_CASE("On a shared body a lossless string's energy changes in each step by the bridge's work on it, "
          "-F (W - w^{n-1}) / 2",
          "[body][energy]")
{
    // BodyReach's budgets rest on this: sitar-bridge plucked, alone on the lossless tanpura body.
    const ModalBody body = tanpuraBody(true);
    auto strings = stringsOf({scene("sitar-bridge.json")}, {true}, true, true);
    auto& string = strings.solvers[0];
    SharedBody shared(body, 1.0, 1.0 / kRate);
    double wBefore = 0.0, wNow = 0.0;  // w^{n-1}, w^n
    const double H0 = string.energyOnBridge(wNow, wBefore);
    double worst = 0.0, flowed = 0.0;
    for (long n = 0; n < 20000; ++n)
    {
        const double H = string.energyOnBridge(wNow, wBefore);
        shared.step(strings.pointers.data(), 1);
        const double W = shared.bridgeDisplacement();
        const double work = -0.5 * shared.lastBridgeForce() * (W - wBefore);
        worst = std::max(worst, std::abs(string.energyOnBridge(W, wNow) - H - work));
        flowed += std::abs(work);
        wBefore = wNow;
        wNow = W;
    }
    INFO("the energy's change differs from the work by at most " << worst / H0 << " of the energy; the work "
                                                                 << "summed to " << flowed / H0 << " of it");
    CHECK(flowed > 1e-3 * H0);   // measured 0.050
    CHECK(worst < 1e-12 * H0);  // measured 2.0e-14 (+F instead of -F: 8.9e-5)
}

TEST_CASE("On a shared body a step solved again rebuilds its joining points' past from heavily damped modes "
          "without amplifying rounding",
          "[body][energy]")
{
    // The energy test's pair of sitar-bridge strings with losses, their modes from 100 up damped at
    // 5e6 /s: e = exp(-2 sigma dt) = 2.6e-23 per step, so q^{n-1} = (a q^n - q~) / e would multiply
    // the prediction's rounding by 4e22.
    std::vector<Scene> scenes = {scene("sitar-bridge.json"), scene("sitar-bridge.json")};
    for (auto& s : scenes)
        for (int p = 100; p <= kModes; ++p)
            s.string.modeOverrides.push_back({p, std::nullopt, 5e6});
    const ModalBody body = tanpuraBody(true);
    auto chosen = stringsOf(scenes, {true, false}, true, true);
    auto every = stringsOf(scenes, {true, false}, false, true);
    SharedBody chosenBody(body, 1.0, 1.0 / kRate), everyBody(body, 1.0, 1.0 / kRate);
    double H = chosenBody.energy(chosen.pointers.data(), 2);
    const double H0 = H;
    double rise = -1.0, difference = 0.0, norm = 0.0;
    long resolved = 0;
    for (long n = 0; n < 100000; ++n)
    {
        chosenBody.step(chosen.pointers.data(), 2);
        everyBody.step(every.pointers.data(), 2);
        resolved += chosenBody.lastResolved();
        const double next = chosenBody.energy(chosen.pointers.data(), 2);
        rise = std::max(rise, (next - H) / H0);
        H = next;
        for (int i = 0; i < 2; ++i)
        {
            difference += std::pow(chosen.solvers[size_t(i)].pickup() - every.solvers[size_t(i)].pickup(), 2);
            norm += std::pow(every.solvers[size_t(i)].pickup(), 2);
        }
    }
    const double relL2 = std::sqrt(difference / norm);
    INFO(resolved << " steps solved again; the energy's largest rise in a step " << rise << " of H0, pickups' relL2 "
                  << relL2 << " against every point live");
    // Before the prediction kept those modes' q^{n-1}: a rise of 6.7e10 H0 and relL2 4e4 (the
    // string blew up at its first step solved again).
    CHECK(resolved > 0);      // measured 95
    CHECK(rise < 1e-12);      // measured -2.8e-12: the steep modes take some energy at every step
    CHECK(relL2 < 1e-9);      // measured 9.9e-13
}
