// What the renderer reads off the string, and scenes with several obstacles at once.

#include "TestSupport.h"
#include "offline/Analysis.h"
#include "offline/OfflineRender.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>

using namespace jawari;

namespace
{
// One lossless mode: the pickup quantities have closed forms.
Scene singleModeScene(PickupQuantity quantity)
{
    auto scene = parseScene(R"({"format": "jawari-scene/1",
        "string": {"damping": {"law": "none"}},
        "simulation": {"modes": 1, "rate": 1000000, "duration": 0.02}})");
    scene.pickup.quantity = quantity;
    return scene;
}
}  // namespace

TEST_CASE("pickup displacement and velocity and the force on the termination agree for one mode")
{
    const double L = 1.002, x = 0.992, T = 180.5, B = 1.78e-5;
    const long long steps = 20000;
    const auto u = renderInternal(singleModeScene(PickupQuantity::displacement), steps);
    const auto v = renderInternal(singleModeScene(PickupQuantity::velocity), steps);
    const auto F = renderInternal(singleModeScene(PickupQuantity::force), steps);
    REQUIRE(u.size() == size_t(steps));

    const auto string = test::paperString();
    const double omega = 2.0 * std::numbers::pi * buildModalTable(string, 1).frequencyHz[0];
    const double k = std::numbers::pi / L;
    double uPeak = 0.0, vPeak = 0.0, worstForce = 0.0;
    for (long long n = 0; n < steps; ++n)
    {
        uPeak = std::max(uPeak, std::abs(u[n]));
        vPeak = std::max(vPeak, std::abs(v[n]));
        // F = T u_x(0) - EI u_xxx(0) = T k (1 + B) q phi'(0)/k... for one mode: F/u = T k (1 + B) / sin(k x).
        const double expected = u[n] * T * k * (1.0 + B) / std::sin(k * x);
        worstForce = std::max(worstForce, std::abs(F[n] - expected));
    }
    double forcePeak = 0.0;
    for (double f : F)
        forcePeak = std::max(forcePeak, std::abs(f));
    INFO("peak u " << uPeak << " m, peak v " << vPeak << " m/s, omega u " << omega * uPeak << ", force error "
                   << worstForce / forcePeak);
    // Lossless cosine: |v|max = omega |u|max (centred difference at 1 MHz: (omega dt)^2/6 ~ 1e-7).
    CHECK(vPeak == Approx(omega * uPeak).epsilon(1e-5));
    CHECK(worstForce / forcePeak < 1e-9);
    CHECK(forcePeak > 0.0);
}

TEST_CASE("several obstacles at once - a point and a profile and a parabola - share the string")
{
    auto scene = parseScene(R"({"format": "jawari-scene/1",
        "obstacles": [
            {"type": "point", "position": 0.5, "height": -2e-4},
            {"type": "profile", "x": [0.7, 0.71, 0.72], "height": [-3e-4, -2e-4, -3e-4], "stiffness": 1e12, "exponent": 1.5},
            {"type": "parabola", "position": 0.004, "width": 0.008, "curvature": 2.0, "height": 0.0}],
        "simulation": {"modes": 300, "rate": 480000, "duration": 0.2}})");
    RenderOptions options;
    options.logEnergy = true;
    const auto r = renderScene(scene, options);
    REQUIRE(r.output.size() == 9600);
    double peak = 0.0;
    for (double y : r.output)
    {
        REQUIRE(std::isfinite(y));
        peak = std::max(peak, std::abs(y));
    }
    long contactSamples = 0;
    for (size_t i = 1; i < r.energy.size(); ++i)
    {
        REQUIRE(r.energy[i].energy <= r.energy[i - 1].energy * (1.0 + 1e-12));
        contactSamples += r.energy[i].contactEnergy > 0.0;
    }
    INFO("peak " << peak << ", samples in contact " << contactSamples << ", max penetration "
                 << r.stats.maxPenetrationMetres);
    CHECK(contactSamples > 100);
    CHECK(peak < 2e-3);
    CHECK(r.stats.maxPenetrationMetres < 1e-5);
}

TEST_CASE("the accuracy measures relative L2 and log-spectral distance and the 20 kHz low-pass are right")
{
    const double rate = 48000.0;
    std::vector<double> x(48000), y(48000), mix(48000);
    for (size_t n = 0; n < x.size(); ++n)
    {
        const double t = double(n) / rate;
        x[n] = std::sin(2 * std::numbers::pi * 440.0 * t) + 0.3 * std::sin(2 * std::numbers::pi * 5000.0 * t);
        y[n] = 2.0 * x[n];
        mix[n] = x[n] + 0.5 * std::sin(2 * std::numbers::pi * 22000.0 * t);
    }
    CHECK(relativeL2(x, x, x.size()) == 0.0);
    CHECK(relativeL2(y, x, x.size()) == Approx(1.0).epsilon(1e-12));
    CHECK(logSpectralDistance(x, x, rate) == 0.0);
    // Twice the amplitude is +6.02 dB in every bin above the floor, and the floor is common.
    const double lsd = logSpectralDistance(y, x, rate);
    INFO("LSD of a 6 dB gain: " << lsd);
    CHECK(lsd > 1.0);
    CHECK(lsd <= 20.0 * std::log10(2.0) + 1e-9);
    const auto filtered = lowpass(mix, rate, 20000.0);
    CHECK(relativeL2(filtered, x, x.size()) < 1e-9);
    CHECK(peakFrequency(x, rate, 300, 600) == Approx(440.0).epsilon(1e-5));
}

TEST_CASE("the band envelope and the centroid track measure levels and the buzz band, not phase")
{
    const double rate = 48000.0;
    std::vector<double> x(48000), louder(48000), shifted(48000);
    for (size_t n = 0; n < x.size(); ++n)
    {
        const double t = double(n) / rate;
        for (int k = 1; k <= 30; ++k)
        {
            const double w = 2 * std::numbers::pi * 220.0 * k * t, a = 1.0 / k;
            x[n] += a * std::sin(w);
            shifted[n] += a * std::sin(w + 0.7 * k * k);  // the same partials, other phases
        }
        louder[n] = 2.0 * x[n];
    }
    CHECK(bandEnvelopeDistance(x, x, rate) == 0.0);
    // Twice the amplitude: +6.02 dB in each band above the floor (bands below it stay floored).
    const double gain = bandEnvelopeDistance(louder, x, rate);
    // Other phases: relL2 near sqrt(2), the envelope within a fraction of a dB.
    const double phase = bandEnvelopeDistance(shifted, x, rate);
    INFO("6 dB gain: " << gain << " dB; other phases: " << phase << " dB, relL2 " << relativeL2(shifted, x, x.size()));
    CHECK(gain > 4.0);
    CHECK(gain <= 20.0 * std::log10(2.0) + 1e-9);
    CHECK(relativeL2(shifted, x, x.size()) > 1.0);
    CHECK(phase < 0.5);

    // From the 10th partial (2.2 kHz) up, the centroid of the 1/k partials' powers.
    const auto track = centroidTrack(x, rate, 2090.0, 20000.0);
    REQUIRE(track.size() == 39);  // 50 ms frames, hop 25 ms, over 1 s
    double expected = 0.0, weight = 0.0;
    for (int k = 10; k <= 30; ++k)
    {
        expected += 220.0 * k / (k * k);
        weight += 1.0 / (k * k);
    }
    expected /= weight;
    INFO("centroid " << track[10] << " Hz, expected " << expected);
    CHECK(track[10] == Approx(expected).epsilon(0.02));
    CHECK(centroidTrackDistance(x, x, rate, 2090.0, 20000.0) == 0.0);
    // The band alone (partials 10 to 30), and every one of them 10 % higher: the centroid 10 % up.
    std::vector<double> band(48000), raised(48000);
    for (size_t n = 0; n < band.size(); ++n)
        for (int k = 10; k <= 30; ++k)
        {
            const double w = 2 * std::numbers::pi * 220.0 * k * double(n) / rate;
            band[n] += std::sin(w) / k;
            raised[n] += std::sin(1.1 * w) / k;
        }
    const double moved = centroidTrackDistance(raised, band, rate, 1000.0, 20000.0);
    INFO("centroid track distance of a 10 % rise: " << moved);
    CHECK(moved == Approx(0.1).margin(0.005));
}
