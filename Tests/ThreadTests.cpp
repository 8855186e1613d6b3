// The damped thread of van Walstijn, Bridges & Mehes (DAFx-16): a bilateral spring-damper the
// string never leaves, spread over the thread's width, and their C3 string's figures: the
// dispersion precursor (their Fig. 7) and what the thread does to it.

#include "TestSupport.h"
#include "offline/Analysis.h"
#include "offline/OfflineRender.h"
#include "physics/contact/ContactLaw.h"
#include "physics/string/ForcePluck.h"
#include "physics/string/SpringLoadedModes.h"
#include "physics/string/StringDiscretisation.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

using namespace jawari;

TEST_CASE("a bilateral law's chord slope is its spring's chord plus its damper, on both sides", "[thread]")
{
    ContactLaw law;
    law.bilateral = true;
    law.exponent = 1.0;
    law.stiffness = 1e8;  // N/m per m
    law.damping = 1e3;    // kg/s per m
    law = solverLaw(law, 1e-6);
    REQUIRE(law.stepDamping == Approx(5e8));
    for (double s : {-2e-5, 0.0, 3e-5})
        for (double r : {-4e-5, -1e-9, 2e-6, 5e-5})
        {
            // The work of the force over r is the spring's energy given back less what the damper took.
            const double work = -chordSlope(law, s, r).value * r;
            const double expected =
                contactPotential(law, s) - contactPotential(law, s - r) - law.stepDamping * r * r;
            INFO("s " << s << ", r " << r);
            CHECK(work == Approx(expected).epsilon(1e-9).margin(1e-30));  // the expected cancels
            for (double b : {-1e-5, 0.0, 2e-5})
            {
                const double k = 1e-13;
                const auto sol = solveScalarContact(law, s, b, k);
                CHECK(std::abs(sol.r + k * sol.slope - b) <= 1e-15 * (std::abs(b) + std::abs(sol.r)) + 1e-30);
                CHECK(sol.slope == Approx(chordSlope(law, s, sol.r).value).epsilon(1e-14));
            }
        }
    CHECK(contactPotential(law, -3e-5) == Approx(0.5 * 1e8 * 9e-10));  // both sides store
}

TEST_CASE("a damped thread's points follow DAFx-16's raised cosine over its width and weigh that width", "[thread]")
{
    Thread thread;
    thread.model = ThreadModel::springDamper;
    thread.width = 1.2e-3;
    const Obstacle fine = threadObstacle(thread, 0.005, 0.0, 1e-4);
    CHECK(fine.law.bilateral);
    CHECK(fine.law.stiffness * fine.width == Approx(1.2e5));
    CHECK(fine.law.damping * fine.width == Approx(1.2));
    const auto points = contactPointsOnGrid({fine}, 1.0, 1000);
    REQUIRE(points.size() == 11);  // 4.5 .. 5.5 mm, strictly inside 4.4 .. 5.6 mm
    double sum = 0.0;
    for (const auto& p : points)
    {
        sum += p.weight;
        const double psi = std::cos(std::numbers::pi * (p.position - 0.005) / 1.2e-3);
        CHECK(p.weight / points[5].weight == Approx(psi).epsilon(1e-9));  // the centre's weight is psi = 1
    }
    CHECK(sum == Approx(1.2e-3).epsilon(1e-12));
    // On the default grid (about 1 mm) the thread is one point at the node inside it, of its width.
    const auto coarse = contactPointsOnGrid({threadObstacle(thread, 0.005, 0.0, 0.0)}, 1.0, 1002);
    REQUIRE(coarse.size() == 1);
    CHECK(coarse[0].weight == Approx(1.2e-3));
    CHECK(coarse[0].position == Approx(5.0 / 1002).epsilon(1e-12));
}

namespace
{
// DAFx-16's C3 string (Resources/Scenes/dafx16-c3.json: their Table 1, the flat bridge at 10 mm,
// the thread at 5 mm, the force pluck), rendered by the reference, with a change.
template <typename Change>
std::vector<double> renderC3(Change&& change)
{
    auto scene = test::scene("dafx16-c3.json");
    change(scene);
    return renderScene(scene).output;
}

Scene& withoutThread(Scene& scene)
{
    scene.obstacles.erase(std::remove_if(scene.obstacles.begin(), scene.obstacles.end(),
                                         [](const Obstacle& o) { return o.law.bilateral; }),
                          scene.obstacles.end());
    return scene;
}

struct Precursor
{
    double median = 0.0;   // s: the median lead over the frames centred 0.10 .. 1.15 s
    double largest = 0.0;  // s
    double leading = 0.0;  // the share of those frames whose high band leads
};

Precursor precursor(const std::vector<double>& y, double rateHz)
{
    const double f1 = peakFrequency(y, rateHz, 100.0, 170.0);
    auto leads = precursorLeads(y, rateHz, f1);
    leads.erase(leads.begin());  // the frame centred 0.05 s holds the pluck itself
    Precursor p;
    p.largest = *std::max_element(leads.begin(), leads.end());
    p.leading = double(std::count_if(leads.begin(), leads.end(), [](double l) { return l > 0.0; })) / double(leads.size());
    std::nth_element(leads.begin(), leads.begin() + leads.size() / 2, leads.end());
    p.median = leads[leads.size() / 2];
    return p;
}

// The share of the first second's energy (Hann) above the 10th partial.
double shareAboveTenthPartial(const std::vector<double>& y, double rateHz)
{
    const double f1 = peakFrequency(y, rateHz, 100.0, 170.0);
    const size_t count = static_cast<size_t>(rateHz);
    std::vector<double> second(y.begin(), y.begin() + std::ptrdiff_t(count));
    double mean = 0.0;
    for (double v : second)
        mean += v / double(count);
    for (double& v : second)
        v -= mean;
    const auto p = powerSpectrum(second.data(), count, count);
    double above = 0.0, all = 0.0;
    for (size_t k = 1; k < p.size(); ++k)
    {
        all += p[k];
        if (double(k) * rateHz / double(count) > 10.0 * f1)
            above += p[k];
    }
    return above / all;
}
}  // namespace

TEST_CASE("DAFx-16's C3 string: the precursor arrives before the low partials with stiffness and not without",
          "[thread][dafx16]")
{
    const double rate = 44100.0;
    const auto stiff = precursor(renderC3([](Scene&) {}), rate);
    const auto flexible = precursor(renderC3([](Scene& s) { s.string.inharmonicity = 0.0; }), rate);
    INFO("precursor lead, median / largest / share leading: with stiffness " << stiff.median * 1e3 << " ms / "
         << stiff.largest * 1e3 << " ms / " << stiff.leading << "; EI = 0 " << flexible.median * 1e3 << " ms / "
         << flexible.largest * 1e3 << " ms / " << flexible.leading);
    CHECK(stiff.median > 0.3e-3);  // measured 0.507 ms
    CHECK(stiff.leading >= 0.9);   // measured 22 of 22 frames
    CHECK(flexible.largest < 0.1e-3);  // measured 0.023 ms
    CHECK(std::abs(flexible.median) < 0.1e-3);  // measured -0.007 ms
}

TEST_CASE("DAFx-16's C3 string: the precursor's centroid falls, faster with the thread nearer the end, and the "
          "string is harsher without its thread",
          "[thread][dafx16]")
{
    const double rate = 44100.0;
    auto threadAt = [](double x) {
        return [x](Scene& s) {
            for (auto& o : s.obstacles)
                if (o.law.bilateral)
                    o.position = x;
        };
    };
    const double atFive = test::centroidFall(renderC3([](Scene&) {}), rate);
    const double atFour = test::centroidFall(renderC3(threadAt(0.004)), rate);
    const double atEight = test::centroidFall(renderC3(threadAt(0.008)), rate);
    INFO("centroid late / early: thread at 4 mm " << atFour << ", 5 mm " << atFive << ", 8 mm " << atEight);
    CHECK(atFive < 0.93);                              // measured 0.859
    CHECK(1.0 - atFour > 1.5 * (1.0 - atEight));       // measured 0.245 against 0.124

    auto endForce = [](Scene& s) { s.pickup.quantity = PickupQuantity::force; };
    const double with = shareAboveTenthPartial(renderC3(endForce), rate);
    const double without = shareAboveTenthPartial(renderC3([&](Scene& s) { endForce(withoutThread(s)); }), rate);
    INFO("the end force's energy above the 10th partial: " << without << " without the thread, " << with << " with it");
    CHECK(without > 1.2 * with);  // measured 0.426 against 0.316
}

TEST_CASE("scenes name a thread's model, lay it alone or across a bridge, push with DAFx-16's force, and refuse "
          "what has no meaning",
          "[thread][scene]")
{
    const auto c3 = test::scene("dafx16-c3.json");
    REQUIRE(c3.obstacles.size() == 2);
    CHECK(c3.obstacles[1].type == ObstacleType::band);
    CHECK(c3.obstacles[1].position == 0.005);
    CHECK(c3.obstacles[1].law.stiffness * c3.obstacles[1].width == Approx(1.2e5));
    REQUIRE(c3.excitation.force);
    CHECK(c3.excitation.force->amplitude == -0.4);
    CHECK(forcePluckNewtons(*c3.excitation.force, 0.0) == 0.0);
    CHECK(forcePluckNewtons(*c3.excitation.force, 0.05) == Approx(0.0).margin(1e-12));
    double strongest = 0.0, when = 0.0;
    for (int i = 0; i <= 5000; ++i)
        if (const double f = forcePluckNewtons(*c3.excitation.force, i * 1e-5); f < strongest)
        {
            strongest = f;
            when = i * 1e-5;
        }
    CHECK(strongest == Approx(-0.4).epsilon(1e-6));
    CHECK(when > 0.045);  // strongest just before it lets go (46 ms)

    // Across a bridge, by the rule from its width.
    const auto laid = parseScene(R"({"format": "jawari-scene/1",
        "obstacles": [{"type": "parabola", "position": 0.005, "width": 0.01, "curvature": 20},
                      {"type": "thread", "bridge": 0, "offset": 0.006, "width": 0.002}]})");
    CHECK(laid.obstacles[1].type == ObstacleType::band);
    CHECK(laid.obstacles[1].law.stiffness * 0.002 == Approx(2e5));
    CHECK(laid.obstacles[1].law.damping * 0.002 == Approx(2.0));

    auto refuses = [](const std::string& body, const std::string& expected) {
        const std::string text = R"({"format": "jawari-scene/1", )" + body + "}";
        INFO(text);
        CHECK_THROWS_WITH(parseScene(text), Catch::Contains(expected));
    };
    refuses(R"("obstacles": [{"type": "thread", "position": 0.005, "exponent": 1.5}])",
            "obstacles[0].exponent: has no meaning for a spring_damper thread");
    refuses(R"("obstacles": [{"type": "thread", "position": 0.005, "damping": -1}])", "obstacles[0].damping");
    refuses(R"("obstacles": [{"type": "thread", "position": 1.5}])", "obstacles[0].position: must lie on the string");
    refuses(R"("obstacles": [{"type": "thread", "position": 0.005, "model": "glue"}])", "obstacles[0].model");
    refuses(R"("excitation": {"type": "force", "position": 0.2, "width": 1.0}, "simulation": {"method": "reference"})",
            "excitation.width: spreads the force");
    refuses(R"("excitation": {"type": "force"}, "simulation": {"method": "realtime"})",
            "excitation.type: \"force\" is rendered by the reference only");
    refuses(R"("excitation": {"type": "force", "duration": 0})", "excitation.duration: must be > 0");
}

TEST_CASE("the pitch a damped thread gives: the spring-loaded mode from Rayleigh quotient iteration is the dense "
          "eigensolver's",
          "[thread]")
{
    // The paper's string with 150 modes, DAFx-16's thread at 6 mm on a 0.5 mm grid (3 points) and a
    // bridge point beside it (unilateral: not a spring at rest).
    const auto s = test::paperString(DampingLaw::none);
    Thread thread;
    thread.model = ThreadModel::springDamper;
    const std::vector<Obstacle> obstacles{threadObstacle(thread, 0.006, 0.0, 0.5e-3), test::pointObstacle(0.004)};
    auto config = stringSolverConfig(s, obstacles, 150, 96000.0, 0.992, PickupQuantity::displacement);
    constexpr int B = 3;  // the thread's points, first
    const int P = static_cast<int>(config.contacts.size());
    REQUIRE(P == B + 1);
    const int N = config.modes.size();
    for (bool compliance : {false, true})
    {
        if (compliance)  // a stand-in for the dropped modes: 1e-6 m/N on each point, half that between them
        {
            config.contactCompliance.assign(size_t(P * P), 0.0);
            for (int a = 0; a < P; ++a)
                for (int b = 0; b < P; ++b)
                    config.contactCompliance[size_t(a * P + b)] = a == b ? 1e-6 : 0.5e-6;
        }
        Eigen::MatrixXd A = Eigen::MatrixXd::Zero(N, N);
        for (int p = 0; p < N; ++p)
            A(p, p) = config.modes.omega[size_t(p)] * config.modes.omega[size_t(p)];
        Eigen::MatrixXd S(B, N);
        Eigen::MatrixXd C = Eigen::MatrixXd::Zero(B, B);
        for (int j = 0; j < B; ++j)
        {
            REQUIRE(config.contacts[size_t(j)].law.bilateral);
            for (int p = 0; p < N; ++p)
                S(j, p) = modeShape(s.lengthMetres, p + 1, config.contacts[size_t(j)].position);
            C(j, j) = 1.0 / (config.contacts[size_t(j)].weight * config.contacts[size_t(j)].law.stiffness);
            if (compliance)
                for (int k = 0; k < B; ++k)
                    C(j, k) += config.contactCompliance[size_t(j * P + k)];
        }
        A += S.transpose() * C.inverse() * S / s.linearDensity;
        const double dense = std::sqrt(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(A).eigenvalues()(0))
                             / (2.0 * std::numbers::pi);
        const double loaded = springLoadedFrequencyHz(config, 0);
        INFO((compliance ? "with" : "without") << " a compliance: free " << config.modes.frequencyHz[0]
                                               << " Hz, with the thread " << loaded << " Hz, dense " << dense << " Hz");
        CHECK(loaded == Approx(dense).epsilon(1e-10));  // the dense solve: 1e-16 of the largest, 3e10
        CHECK(loaded > config.modes.frequencyHz[0] * 1.001);  // the thread raises the pitch
    }
}
