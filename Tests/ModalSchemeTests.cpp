// The string's modal table and the exact per-mode update (docs/design.md sections 1 and 2).

#include "TestSupport.h"
#include "physics/modes/ExactOscillator.h"
#include "physics/modes/ModalSolver.h"
#include "physics/string/StringDiscretisation.h"
#include "physics/string/StringModel.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

using namespace jawari;

TEST_CASE("modal frequencies follow f_p = p f0 sqrt(1 + B p^2) and measured modes override them")
{
    auto s = test::paperString();
    s.modeOverrides.push_back({1, 195.7, 0.9});
    s.modeOverrides.push_back({3, std::nullopt, 2.5});
    const auto t = buildModalTable(s, 1001);
    const double f0 = std::sqrt(180.5 / 1.17e-3) / (2.0 * 1.002);
    CHECK(s.flexibleFundamentalHz() == Approx(f0).epsilon(1e-15));
    CHECK(t.frequencyHz[0] == 195.7);
    CHECK(t.sigma[0] == 0.9);
    CHECK(t.frequencyHz[1] == Approx(2.0 * f0 * std::sqrt(1.0 + 1.78e-5 * 4.0)).epsilon(1e-14));
    CHECK(t.frequencyHz[1000] == Approx(1001.0 * f0 * std::sqrt(1.0 + 1.78e-5 * 1001.0 * 1001.0)).epsilon(1e-14));
    CHECK(t.sigma[2] == 2.5);
    CHECK(t.frequencyHz[2] == Approx(3.0 * f0 * std::sqrt(1.0 + 1.78e-5 * 9.0)).epsilon(1e-14));
}

TEST_CASE("Valette's damping law gives the paper's quality factors")
{
    const auto s = test::paperString();
    constexpr double pi = std::numbers::pi;
    const double f = 1000.0;
    const double EI = 1.78e-5 * 180.5 * 1.002 * 1.002 / (pi * pi);
    const double R = 2 * pi * 1.8e-5 + 2 * pi * 0.43e-3 * std::sqrt(pi * 1.8e-5 * 1.2 * f);
    const double expected =
        R / (2 * pi * 1.17e-3 * f) + 4 * pi * pi * 1.17e-3 * EI * 0.006 * f * f / (180.5 * 180.5) + 1.38e-4;
    CHECK(valetteInverseQ(s, f) == Approx(expected).epsilon(1e-14));
    const auto t = buildModalTable(s, 20);
    CHECK(t.sigma[4] == Approx(pi * t.frequencyHz[4] * valetteInverseQ(s, t.frequencyHz[4])).epsilon(1e-14));
    // The top modes of the paper's grid are close to critically damped: both branches are used.
    const auto top = buildModalTable(s, 1001);
    CHECK(top.sigma[1000] > 0.5 * top.omega[1000]);
}

TEST_CASE("The wavenumber damping law gives DAFx-16's decay rates for its C3 string")
{
    // van Walstijn, Bridges & Mehes (DAFx-16), eq. 18 and Table 1: sigma_i = sigma0 + sigma1 beta_i
    // + sigma3 beta_i^3, beta_i = i pi / L, with 0.6 1/s, 6.5e-3 m/s and 5e-6 m^3/s on a 1 m string.
    StringParameters s;
    s.lengthMetres = 1.0;
    s.tensionNewtons = 33.1;
    s.linearDensity = 4.83e-4;
    s.damping.law = DampingLaw::wavenumber;
    s.damping.sigma0 = 0.6;
    s.damping.sigma1 = 6.5e-3;
    s.damping.sigma3 = 5e-6;
    const auto t = buildModalTable(s, 133);
    constexpr double pi = std::numbers::pi;
    CHECK(t.sigma[0] == Approx(0.6 + 6.5e-3 * pi + 5e-6 * pi * pi * pi).epsilon(1e-14));  // 0.621 1/s
    const double beta = 133 * pi;
    CHECK(t.sigma[132] == Approx(0.6 + 6.5e-3 * beta + 5e-6 * beta * beta * beta).epsilon(1e-14));
    CHECK(t.sigma[132] == Approx(368.05).epsilon(1e-4));  // the 20 kHz mode decays in 2.7 ms
}

TEST_CASE("the multiplied-out update is the paper's scheme (eq. 5) and its energy coefficients")
{
    // Paper: alpha_i = 2/(w dt)^2 - A/(1+e-A), sigma* = (1/dt + w^2 dt/2 (1 - alpha)) (1-e)/(1+e),
    // C1 = c/D, C2 = w^2/D, C3 = 2 sigma*/D with c = 1 + (1-alpha) w^2 dt^2/2, D = c + sigma* dt.
    for (double sigma : {0.0, 3.0, 800.0})
        for (double dt : {1.0 / 48000.0, 1.0 / 2e6})
        {
            const double w = 2 * std::numbers::pi * 1500.0;
            const auto c = exactCoefficients(w, sigma, dt);
            const double A = c.a, e = c.e;
            const double alpha = 2.0 / (w * w * dt * dt) - A / (1.0 + e - A);
            const double cc = 1.0 + (1.0 - alpha) * w * w * dt * dt / 2.0;
            const double sigmaStar = (1.0 / dt + w * w * dt / 2.0 - alpha * w * w * dt / 2.0) * (1.0 - e) / (1.0 + e);
            const double D = cc + sigmaStar * dt;
            INFO("sigma " << sigma << " dt " << dt);
            CHECK(c.kineticWeight == Approx(cc / D).epsilon(1e-6));
            CHECK(c.potentialWeight == Approx(w * w / D).epsilon(1e-6));
            CHECK(c.lossWeight == Approx(dt * 2.0 * sigmaStar / D).epsilon(1e-6).margin(1e-300));
            // The update (C1 dtt + C2 + C3 dt.) q = 0 multiplied out: a = (2c - w^2 dt^2)/D, e = (c - s* dt)/D.
            CHECK(A == Approx((2 * cc - w * w * dt * dt) / D).epsilon(1e-6));
            CHECK(e == Approx((cc - sigmaStar * dt) / D).epsilon(1e-6));
        }
}

TEST_CASE("a mode damped far beyond its frequency keeps finite coefficients: its slow decay per step")
{
    // Valette's viscoelastic loss grows as f^3: the reference's 4001st mode on the sitar's string
    // has sigma dt ~ 2700 at 2 MHz, where cosh(wh dt) overflows and exp(-sigma dt) underflows.
    const double w = 2 * std::numbers::pi * 1.1e7, dt = 1.0 / 2e6;
    for (double sigmaDt : {300.0, 699.0, 701.0, 2700.0, 1e5})
    {
        const double sigma = sigmaDt / dt;
        const auto c = exactCoefficients(w, sigma, dt);
        INFO("sigma dt " << sigmaDt);
        CHECK(std::isfinite(c.a));
        // sigma >> omega: the slow root exp(-dt omega^2 / (sigma + wh)) and no fast one.
        const double wh = std::sqrt(sigma * sigma - w * w);
        CHECK(c.a == Approx(std::exp(-dt * w * w / (sigma + wh))).epsilon(1e-12));
        CHECK(c.e == Approx(std::exp(-2.0 * sigmaDt)).margin(1e-300));
        // One step on from rest at 1: the slow root alone.
        CHECK(freeDampedMotion(1.0, 0.0, w, sigma, dt) == Approx(c.a * (sigma + wh) / (2.0 * wh)).epsilon(1e-12));
    }
}

TEST_CASE("without contact every mode follows the analytic damped solution to 1e-9 at any dt")
{
    // The paper's string with its damping law (the top modes near critical damping) plus a constant
    // law strong enough to overdamp the first modes.
    for (auto law : {DampingLaw::valette, DampingLaw::constant, DampingLaw::none})
        for (double rate : {44100.0, 48000.0 * 4, 1e6, 2e6})
        {
            auto s = test::paperString(law);
            s.damping.sigma = 3000.0;  // overdamps modes below ~480 Hz in the constant law
            const int M = 300;
            auto config = test::gridConfig(s, M, rate, {});
            ModalSolver solver(config);
            const auto q0 = pluckModalShape(s.lengthMetres, M, 0.3, 1e-3);
            solver.setInitialDisplacement(q0);
            const int steps = 20000;
            for (int n = 0; n < steps; ++n)
                solver.step();
            const auto q = solver.modalState();
            // Each mode to 1e-9 of its own amplitude; modes below 1e-9 of the largest (like mode 167
            // here, whose sine vanishes at x = 0.3: 5e-20 of the largest, and skipped by the solver as
            // rounding) to 1e-9 of that floor, i.e. 1e-18 of the largest mode.
            double largest = 0.0;
            for (double v : q0)
                largest = std::max(largest, std::abs(v));
            double worst = 0.0;
            for (int p = 0; p < M; ++p)
            {
                const double exact =
                    freeDampedMotion(q0[p], 0.0, config.modes.omega[p], config.modes.sigma[p], steps / rate);
                worst = std::max(worst, std::abs(q[p] - exact) / std::max(std::abs(q0[p]), 1e-9 * largest));
            }
            INFO("law " << int(law) << " rate " << rate << " worst relative error " << worst);
            CHECK(worst < 1e-9);
        }
}

namespace
{
// A lossless string of 100 modes at 96 kHz plucked, stepped 5000 steps, then retuned `swings` times
// between ratio 1 and 1.06 (a semitone), 37 steps apart (a phase of every mode): its energy at the
// end against its energy before the first retune, and the largest departure of a retune's energy
// ratio from the frequency ratio.
struct Swings
{
    double drift = 0.0, worstRatio = 0.0;
};
Swings retunedBackAndForth(ModalSolver::RetuneMotion motion, bool staticExact, int swings)
{
    auto s = test::paperString(DampingLaw::none);
    auto config = stringSolverConfig(s, {}, 100, 96000.0, 0.992, PickupQuantity::displacement);
    config.staticExactForcing = staticExact;
    ModalSolver solver(config);
    solver.setInitialDisplacement(pluckModalShape(s.lengthMetres, 100, 0.18, 1e-3));
    for (int n = 0; n < 5000; ++n)
        solver.step();
    const double H0 = solver.stringEnergy();
    auto omega = config.modes.omega;
    Swings out;
    for (int k = 0; k < swings; ++k)
    {
        const double ratio = k % 2 == 0 ? 1.06 : 1.0 / 1.06;
        for (auto& w : omega)
            w *= ratio;
        const double before = solver.stringEnergy();
        solver.retune(omega.data(), config.modes.sigma.data(), 1.0, 1.0, motion);
        out.worstRatio = std::max(out.worstRatio, std::abs(solver.stringEnergy() / before / ratio - 1.0));
        for (int n = 0; n < 37; ++n)
            solver.step();
    }
    out.drift = std::abs(solver.stringEnergy() / H0 - 1.0);
    return out;
}
}  // namespace

TEST_CASE("A sounding string retuned with its modes' actions kept: each retune by r multiplies its lossless "
          "energy by r, and a thousand swings of a semitone return it to its energy; kept still, they pump it")
{
    using Motion = ModalSolver::RetuneMotion;
    for (const bool staticExact : {false, true})
    {
        const auto kept = retunedBackAndForth(Motion::keepActions, staticExact, 1000);
        const auto still = retunedBackAndForth(Motion::keepState, staticExact, 1000);
        INFO("static-exact " << staticExact << ": actions kept, drift " << kept.drift << " (each retune within "
                             << kept.worstRatio << " of r); state kept, drift " << still.drift);
        CHECK(kept.worstRatio < 1e-9);
        CHECK(kept.drift < 1e-9);
        CHECK(still.drift > 1e-3);
    }
}
