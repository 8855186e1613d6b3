// The paper's two experiments (docs/design.md section 3) run by the reference solver.

#include "TestSupport.h"
#include "offline/Analysis.h"
#include "offline/OfflineRender.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace jawari;

namespace
{
struct PaperRuns
{
    RenderResult centre, tanpura, free;
};

const PaperRuns& paperRuns()
{
    static const PaperRuns runs = [] {
        PaperRuns r;
        RenderOptions options;
        options.logEnergy = true;
        auto centre = test::scene("paper-centre.json");
        r.centre = renderScene(centre, options);
        r.tanpura = renderScene(test::scene("paper-tanpura.json"), options);
        centre.obstacles.clear();
        r.free = renderScene(centre, options);
        return r;
    }();
    return runs;
}
}  // namespace

TEST_CASE("paper-centre: the obstacle raises the fundamental by 4/3 (Cabannes 1981) within 0.3%")
{
    const auto& runs = paperRuns();
    // Strongest peak between 150 and 400 Hz: either the free fundamental (~196 Hz) or 4/3 of it.
    const double withObstacle = peakFrequency(runs.centre.output, 48000, 150, 400);
    const double without = peakFrequency(runs.free.output, 48000, 150, 400);
    INFO("fundamental without " << without << " Hz, with " << withObstacle << " Hz, ratio " << withObstacle / without);
    CHECK(without == Approx(196.0).epsilon(0.003));
    CHECK(withObstacle / without == Approx(4.0 / 3.0).epsilon(0.003));
}

TEST_CASE("paper-tanpura has a descending formant and decays faster than paper-centre")
{
    const auto& runs = paperRuns();
    const auto& y = runs.tanpura.output;
    const double f0 = peakFrequency(runs.free.output, 48000, 150, 400);
    // Spectral centroid of the band above the 10th partial, early and late in the first second,
    // against the same string without its obstacle.
    test::checkBandFalls(y, runs.free.output, f0);

    const double centreRatio = runs.centre.energy.back().energy / runs.centre.energy.front().energy;
    const double tanpuraRatio = runs.tanpura.energy.back().energy / runs.tanpura.energy.front().energy;
    INFO("H(1 s)/H(0): centre " << centreRatio << ", tanpura " << tanpuraRatio);
    CHECK(tanpuraRatio < 0.5 * centreRatio);
}

TEST_CASE("the paper scenes are stable with finite output and bounded penetration and Newton work")
{
    const auto& runs = paperRuns();
    for (const auto* r : {&runs.centre, &runs.tanpura})
    {
        double peak = 0.0;
        for (double v : r->output)
        {
            REQUIRE(std::isfinite(v));
            peak = std::max(peak, std::abs(v));
        }
        INFO("peak " << peak << " m, max penetration " << r->stats.maxPenetrationMetres << " m, Newton max "
                     << r->stats.newtonIterationsMax);
        CHECK(peak < 2e-3);
        CHECK(r->stats.maxPenetrationMetres < 1e-6);
        CHECK(r->stats.newtonIterationsMax <= 50);
        // Energy is only ever lost.
        for (size_t i = 1; i < r->energy.size(); ++i)
            REQUIRE(r->energy[i].energy <= r->energy[i - 1].energy * (1.0 + 1e-12));
    }
}
