// The reference solver's two contact paths (docs/design.md section 2): projection (few points) and
// DST-I (many points) must agree to rounding on the grid.

#include "TestSupport.h"
#include "offline/OfflineRender.h"
#include "physics/modes/ModalSolver.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

using namespace jawari;

namespace
{
struct Comparison
{
    double worst = 0.0;
    double peak = 0.0;
    long contactSteps = 0;
};

Comparison compare(ModalSolverConfig a, ModalSolverConfig b, const std::vector<double>& q0, long steps)
{
    ModalSolver first(a), second(b);
    first.setInitialDisplacement(q0);
    second.setInitialDisplacement(q0);
    Comparison c;
    for (long n = 0; n < steps; ++n)
    {
        first.step();
        second.step();
        if (first.lastMaxPenetration() > 0.0)
            ++c.contactSteps;
        c.peak = std::max(c.peak, std::abs(first.pickup()));
        c.worst = std::max(c.worst, std::abs(first.pickup() - second.pickup()));
    }
    return c;
}
}  // namespace

TEST_CASE("a point obstacle on the grid: projection and DST paths agree to rounding")
{
    const auto s = test::paperString();
    const int M = 1001;
    const std::vector<Obstacle> obstacles{test::pointObstacle(0.501)};
    const auto q0 = pluckModalShape(s.lengthMetres, M, 0.501, 1.5e-3);
    const auto c = compare(test::gridConfig(s, M, 2e6, obstacles, ContactPath::projection),
                           test::gridConfig(s, M, 2e6, obstacles, ContactPath::transform), q0, 40000);
    INFO("max |difference| / peak = " << c.worst / c.peak << " over " << c.contactSteps << " contact steps");
    CHECK(c.contactSteps > 5000);
    CHECK(c.worst / c.peak < 1e-10);
}

TEST_CASE("a sampled profile: the projection's decoupled solves and the DST path agree to rounding")
{
    const auto s = test::paperString();
    const int M = 1001;
    Obstacle profile;
    profile.type = ObstacleType::profile;
    profile.profileX = {0.0, 0.004, 0.008, 0.012};
    profile.profileHeight = {-3e-5, 0.0, -1e-5, -4e-5};
    profile.law = {1e13, 1.3};
    const std::vector<Obstacle> obstacles{profile};
    const auto q0 = pluckModalShape(s.lengthMetres, M, 0.501, 1.5e-3);
    auto projection = test::gridConfig(s, M, 2e6, obstacles, ContactPath::projection);
    REQUIRE(projection.contacts.size() == 12);  // the interior nodes at 1..12 mm
    const auto c = compare(projection, test::gridConfig(s, M, 2e6, obstacles, ContactPath::transform), q0, 40000);
    INFO("max |difference| / peak = " << c.worst / c.peak << " over " << c.contactSteps << " contact steps");
    CHECK(c.contactSteps > 1000);
    CHECK(c.worst / c.peak < 1e-10);
}

TEST_CASE("the render pipeline gives the same output through either path")
{
    auto scene = test::scene("paper-tanpura.json");
    scene.simulation.durationSeconds = 0.03;
    RenderOptions projection, transform;
    projection.path = ContactPath::projection;
    transform.path = ContactPath::transform;
    const auto a = renderScene(scene, projection);
    const auto b = renderScene(scene, transform);
    REQUIRE(a.output.size() == 1440);
    REQUIRE(b.output.size() == 1440);
    CHECK_FALSE(a.stats.transformPath);
    CHECK(b.stats.transformPath);
    double worst = 0.0, peak = 0.0;
    for (size_t i = 0; i < a.output.size(); ++i)
    {
        worst = std::max(worst, std::abs(a.output[i] - b.output[i]));
        peak = std::max(peak, std::abs(a.output[i]));
    }
    INFO("max |difference| / peak = " << worst / peak);
    CHECK(worst / peak < 1e-10);
}

TEST_CASE("a scene's contact spacing places the reference's points on a bridge, as the bridge's own spacing "
          "would, and leaves an obstacle's own spacing and the voice's points alone")
{
    auto scene = test::atPaperConfiguration(test::scene("sitar-bridge.json"));
    scene.simulation.durationSeconds = 0.03;
    const double L = scene.string.lengthMetres;
    auto render = [](Scene s) { return renderScene(s).output; };
    auto bySimulation = scene;
    bySimulation.simulation.contactSpacingMetres = L / 2004;
    auto byObstacle = scene;
    byObstacle.obstacles.front().spacing = L / 2004;
    const auto grid = render(scene);
    const auto fine = render(bySimulation);
    CHECK(fine == render(byObstacle));
    CHECK(relativeL2(fine, grid, grid.size()) > 1e-4);  // the points moved: another answer
    // An obstacle's own spacing wins over the scene's.
    auto both = byObstacle;
    both.simulation.contactSpacingMetres = L / 4008;
    CHECK(render(both) == fine);
    // The voice keeps its points.
    auto voice = scene;
    voice.simulation.reference = false;
    voice.simulation.modes = 142;
    voice.simulation.rateHz = 3 * 48000.0;
    auto voiceSpaced = voice;
    voiceSpaced.simulation.contactSpacingMetres = L / 2004;
    CHECK(render(voice) == render(voiceSpaced));
}

TEST_CASE("the reference with its rate extrapolated is 2 y(2R) - y(R), and cancels a point contact's first-order "
          "error in the step")
{
    // paper-tanpura's point 6 mm from the end at 1e13 N/m^1.3 (a contact shorter than a step), its
    // 1001 modes over 30 ms: renders at R against (32, 64 MHz) extrapolated. (With 200 modes the rate
    // converges more slowly than at first order, and extrapolating gains nothing.)
    auto scene = test::scene("paper-tanpura.json");
    scene.simulation.durationSeconds = 0.03;
    auto at = [&](double rate, bool extrapolated) {
        Scene s = scene;
        s.simulation.rateHz = rate;
        s.simulation.extrapolateRate = extrapolated;
        return renderScene(s).output;
    };
    const auto y1 = at(2e6, false), y2 = at(4e6, false), x = at(2e6, true);
    REQUIRE(x.size() == y1.size());
    double worst = 0.0;
    for (size_t i = 0; i < x.size(); ++i)
        worst = std::max(worst, std::abs(x[i] - (2.0 * y2[i] - y1[i])));
    CHECK(worst == 0.0);

    const auto truth = at(32e6, true);
    const double plain = relativeL2(at(16e6, false), truth, truth.size());
    const double plainHalf = relativeL2(at(8e6, false), truth, truth.size());
    const double extrapolated = relativeL2(at(8e6, true), truth, truth.size());
    INFO("against (32, 64 MHz) extrapolated: plain 8 MHz " << plainHalf << ", plain 16 MHz " << plain
                                                            << ", (8, 16 MHz) extrapolated " << extrapolated);
    CHECK(plainHalf / plain > 1.6);  // first order: halved with the step
    CHECK(plainHalf / plain < 2.6);
    CHECK(extrapolated < 0.3 * plain);  // what is left is of higher order (measured 9.9e-6 against 4.8e-5)
}

TEST_CASE("the extrapolated reference's two renders, side by side, report one rising progress to 1, and a cancel "
          "stops the render")
{
    auto scene = test::scene("paper-tanpura.json");
    scene.simulation.durationSeconds = 0.1;
    scene.simulation.rateHz = 2e6;
    scene.simulation.extrapolateRate = true;
    RenderOptions options;
    std::vector<double> reported;
    options.progress = [&](double done) {
        reported.push_back(done);
        return true;
    };
    renderScene(scene, options);
    REQUIRE(reported.size() > 3);
    CHECK(std::is_sorted(reported.begin(), reported.end()));
    CHECK(reported.back() == 1.0);

    // Cancelled at the third report (the fine render's, on this thread, every 2^16 of its 4e5 steps):
    // the render throws, the coarse one stopped with it. The fine render was then a third done, so the
    // report is at most (1 + 2 x 0.33) / 3 = 0.55, reached when the coarse one has already finished.
    reported.clear();
    options.progress = [&](double done) {
        reported.push_back(done);
        return reported.size() < 3;
    };
    CHECK_THROWS_WITH(renderScene(scene, options), "render cancelled");
    CHECK(reported.size() == 3);
    CHECK(reported.back() <= (1.0 + 2.0 * 2.0 * 65536.0 / 4e5) / 3.0);
}
