// The modal body under the bridge (ModalBody.h, FactoryBodies.h): its measured response, the energy
// of strings and body together, and the tanpura heard through it (DAFx-16).

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
// The solver's response from a unit impulse of force on the bridge to the radiated pressure: the
// body's modes beside one string mode nothing touches, pushed at the bridge for one step.
std::vector<double> bridgeImpulseResponse(const ModalBody& body, double rateHz, double seconds, int listener = 0)
{
    ModalSolverConfig strings;
    strings.lengthMetres = 1.0;
    strings.linearDensity = 1e-3;
    strings.timeStep = 1.0 / rateHz;
    strings.modes = buildModalTable(test::paperString(), 1);
    strings.excitationPosition = 0.5;
    auto c = withBody(strings, {&body, {}, 1.0});
    c.excitationShape[0] = 0.0;
    for (size_t k = 0; k < body.modes.size(); ++k)  // F on the bridge: m_k z_k'' = F
        c.excitationShape[1 + k] = std::sqrt(strings.linearDensity / body.modes[k].massKg);
    c.pickupWeights = radiationWeights(body, 1, strings.linearDensity, listener);
    ModalSolver solver(c);
    const double dt = strings.timeStep;
    std::vector<double> y{solver.pickup()};
    solver.setExternalForce(1.0 / dt);
    for (long n = 0; n < std::lround(seconds * rateHz); ++n)
    {
        solver.step();
        solver.setExternalForce(0.0);
        y.push_back(solver.pickup());
    }
    // p^n = (y^{n+1} - y^{n-1}) / 2dt, the body at rest before the push (y^{-1} = y^0).
    std::vector<double> p(y.size() - 1);
    for (size_t n = 0; n < p.size(); ++n)
        p[n] = (y[n + 1] - y[n == 0 ? 0 : n - 1]) / (2.0 * dt);
    return p;
}

// The discrete-time Fourier transform of the impulse response p (sampled at rateHz) over each band,
// on a logarithmic grid 1/16 of the narrowest peak's width apart: P(f) / rate at f, f dln(f) its weight.
struct BandSpectrum
{
    std::vector<std::complex<double>> values;
    std::vector<double> weights;
};
std::vector<BandSpectrum> bandSpectra(const std::vector<double>& p, double rateHz, const std::vector<BandLevel>& bands,
                                      double lossFactor)
{
    std::vector<BandSpectrum> out;
    const double ratio = 1.0 + lossFactor / 16.0;
    for (const auto& band : bands)
    {
        BandSpectrum s;
        for (double f = band.lowHz; f < band.highHz; f *= ratio)
        {
            const std::complex<double> turn = std::polar(1.0, -2.0 * std::numbers::pi * f / rateHz);
            std::complex<double> sumP = 0.0, z = 1.0;
            for (double v : p)
            {
                sumP += v * z;
                z *= turn;
            }
            s.values.push_back(sumP / rateHz);
            s.weights.push_back(f * std::log(ratio));
        }
        out.push_back(std::move(s));
    }
    return out;
}

// Mean |P(f)|^2 over each band (the sum of |P(f)|^2 f dln(f) over the band's width), relative to band
// `reference` (dB; re 1 (Pa/N)^2 for reference -1).
std::vector<double> measuredBandLevels(const std::vector<BandSpectrum>& spectra, const std::vector<BandLevel>& bands,
                                       int reference)
{
    std::vector<double> levels;
    for (size_t b = 0; b < bands.size(); ++b)
    {
        double sum = 0.0;
        for (size_t i = 0; i < spectra[b].values.size(); ++i)
            sum += std::norm(spectra[b].values[i]) * spectra[b].weights[i];
        levels.push_back(10.0 * std::log10(sum / (bands[b].highHz - bands[b].lowHz)));
    }
    const double ref = reference < 0 ? 0.0 : levels[size_t(reference)];
    for (double& l : levels)
        l -= ref;
    return levels;
}

// The band's mean |P(f)|^2 (dB re 1 (Pa/N)^2) summed here from the modes' own parameters, as the solver
// answers a force impulse at `rateHz`: each mode's displacement per newton the paper's recurrence,
// Z_k = (dt^2 / m_k) z^-1 / (1 - a_k z^-1 + e_k z^-2) with a_k = 2 exp(-sigma_k dt) cos(w_dk dt),
// e_k = exp(-2 sigma_k dt), the pressure its reading's centred difference (z - z^-1) / 2dt weighted by
// c_k, for the impulse 1/dt a step long (the DTFT times dt: the continuous spectrum's scale); on a grid
// 1/64 of the narrowest peak's width apart.
double modalSumBandLevel(const ModalBody& body, const BandLevel& band, double rateHz)
{
    double narrowest = 1.0;
    for (const auto& m : body.modes)
        narrowest = std::min(narrowest, m.sigma / (std::numbers::pi * m.frequencyHz));
    const double ratio = 1.0 + narrowest / 64.0, dt = 1.0 / rateHz;
    double sum = 0.0;
    for (double f = band.lowHz; f < band.highHz; f *= ratio)
    {
        const std::complex<double> z = std::polar(1.0, 2.0 * std::numbers::pi * f * dt);
        std::complex<double> Z = 0.0;
        for (const auto& m : body.modes)
        {
            const double wk = 2.0 * std::numbers::pi * m.frequencyHz;
            const double a = 2.0 * std::exp(-m.sigma * dt) * std::cos(std::sqrt(wk * wk - m.sigma * m.sigma) * dt);
            const double e = std::exp(-2.0 * m.sigma * dt);
            Z += m.radiation[0] * dt * dt / m.massKg / z / (1.0 - a / z + e / (z * z));
        }
        const std::complex<double> P = (z - 1.0 / z) / (2.0 * dt) * Z;
        sum += std::norm(P) * f * std::log(ratio);
    }
    return 10.0 * std::log10(sum / (band.highHz - band.lowHz));
}

// How alike two responses are over bands from..to (inclusive): Re sum P1 conj(P2) / sqrt(sum |P1|^2
// sum |P2|^2), 1 for the same response, near 0 for unrelated ones.
double correlationOver(const std::vector<BandSpectrum>& one, const std::vector<BandSpectrum>& two, size_t from,
                       size_t to)
{
    double cross = 0.0, first = 0.0, second = 0.0;
    for (size_t b = from; b <= to; ++b)
        for (size_t i = 0; i < one[b].values.size(); ++i)
        {
            const double w = one[b].weights[i];
            cross += w * (one[b].values[i] * std::conj(two[b].values[i])).real();
            first += w * std::norm(one[b].values[i]);
            second += w * std::norm(two[b].values[i]);
        }
    return cross / std::sqrt(first * second);
}

// How many modes a band's response is made of: each mode's share of the band's power at the centre
// listener, c_k^2 / (m_k^2 sigma_k) (its peak's height (c_k / 2 m_k sigma_k)^2 times its width), as
// (sum w)^2 / sum w^2.
double effectiveModes(const ModalBody& body, const BandLevel& band)
{
    double sum = 0.0, squares = 0.0;
    for (const auto& m : body.modes)
        if (m.frequencyHz >= band.lowHz && m.frequencyHz < band.highHz)
        {
            const double w = m.radiation[0] * m.radiation[0] / (m.massKg * m.massKg * m.sigma);
            sum += w;
            squares += w * w;
        }
    return squares > 0.0 ? sum * sum / squares : 0.0;
}

Scene withTanpuraBody(Scene scene, PickupQuantity quantity)
{
    scene.body = SceneBody{*factoryBody("tanpura"), {}, 1.0, {}};
    for (size_t i = 0; i < scene.obstacles.size(); ++i)
        scene.body->obstacles.push_back(int(i));
    scene.pickup.quantity = quantity;
    return scene;
}


// Every string of the scene and its body's modes without damping.
void makeLossless(Scene& scene)
{
    scene.string.damping.law = DampingLaw::none;
    for (auto& s : scene.body->strings)
        s.string.damping.law = DampingLaw::none;
    for (auto& mode : scene.body->body.modes)
        mode.sigma = 0.0;
}

// The scene's reference over 1e5 steps (0.05 s at 2 MHz) with its energy log: the largest drift from
// the initial energy and the largest rise between log rows, both relative to it.
struct EnergyRun
{
    RenderResult result;
    double drift = 0.0, rise = 0.0;
};
EnergyRun referenceEnergy(Scene scene)
{
    scene.simulation.durationSeconds = 0.05;
    RenderOptions options;
    options.logEnergy = true;
    EnergyRun run{renderScene(scene, options)};
    const double H0 = run.result.stats.initialEnergy;
    const auto& log = run.result.energy;
    for (size_t i = 0; i < log.size(); ++i)
    {
        run.drift = std::max(run.drift, std::abs(log[i].energy / H0 - 1.0));
        if (i > 0)
            run.rise = std::max(run.rise, (log[i].energy - log[i - 1].energy) / H0);
    }
    return run;
}
}  // namespace

TEST_CASE("The tanpura body's response from the bridge to the radiated sound follows DAFx-16's measured band "
          "levels within 1 dB, and the sitar body's the same levels at the frequencies its smaller plate scales "
          "them to, measured through the solver; its level in Pa per N the modes' own sum's, and the reference "
          "band the infinite plate's",
          "[body]")
{
    for (const auto* recipe : {&tanpuraBodyRecipe(), &sitarBodyRecipe()})
    {
        // The measured bands from 80 Hz, at the frequencies this body scales them to.
        const double scale = recipe->lowestHz / tanpuraBodyRecipe().lowestHz;
        const auto body = *factoryBody(recipe->name);
        const double rate = 96000.0;
        const auto p = bridgeImpulseResponse(body, rate, 2.0);
        const auto spectra = bandSpectra(p, rate, recipe->bands, recipe->lossFactor);
        const auto levels = measuredBandLevels(spectra, recipe->bands, recipe->referenceBand);
        const auto absolute = measuredBandLevels(spectra, recipe->bands, -1);
        REQUIRE(levels.size() >= 11);
        for (size_t b = 0; b < levels.size(); ++b)
        {
            const auto& band = recipe->bands[b];
            const double modal = modalSumBandLevel(body, band, rate);
            INFO(recipe->name << " (" << body.modes.size() << " modes from " << body.modes.front().frequencyHz
                              << " Hz): " << band.lowHz << "-" << band.highHz << " Hz: " << levels[b] << " dB, wanted "
                              << band.levelDb << " dB; " << absolute[b] << " dB re 1 Pa/N, the modes' sum "
                              << modal << " dB");
            if (band.lowHz >= 0.999 * 80.0 * scale)
                CHECK(std::abs(levels[b] - band.levelDb) < 1.0);  // the fit's promise (fitBands); measured 0.60
            CHECK(std::abs(absolute[b] - modal) < 0.1);  // measured 0.024 dB
        }
        // The reference band at the infinite plate's point-force radiation below coincidence,
        // |p / F| = rho_air / (2 sqrt(2) pi r rho h) at r metres.
        const double plate = 1.2 / (2.0 * std::sqrt(2.0) * std::numbers::pi * recipe->listenerMetres
                                    * recipe->densityKgM3 * recipe->thicknessM);
        INFO(recipe->name << ": the reference band " << absolute[size_t(recipe->referenceBand)]
                          << " dB re 1 Pa/N, the infinite plate's " << 20.0 * std::log10(plate) << " dB");
        CHECK(std::abs(absolute[size_t(recipe->referenceBand)] - 20.0 * std::log10(plate)) < 0.1);  // measured 0.012
    }
    // The sitar's plate, 0.32 m across against the tanpura's 0.40 m, has its modes (and so its
    // response's bands) higher by the ratio of their areas, 1.5625, and fewer of them below 13 kHz.
    const auto& tanpura = tanpuraBodyRecipe();
    const auto& sitar = sitarBodyRecipe();
    CHECK(sitar.lowestHz == Approx(tanpura.lowestHz * 1.5625));
    CHECK(sitar.bands[sitar.referenceBand].lowHz == Approx(tanpura.bands[tanpura.referenceBand].lowHz * 1.5625));
    CHECK(factoryBody("sitar")->modes.size() < 0.7 * factoryBody("tanpura")->modes.size());
}

TEST_CASE("The tanpura body heard left and right of its measured listener: DAFx-16's band levels within 1 dB at "
          "each, the two alike where the plate is small beside the wavelength and apart above it, as a disc's "
          "directions are (van Cittert-Zernike), measured through the solver",
          "[body]")
{
    const auto& recipe = tanpuraBodyRecipe();
    const auto body = *factoryBody("tanpura");
    REQUIRE(body.listeners == std::vector<std::string>{"centre", "left", "right"});
    const double rate = 96000.0;
    std::vector<std::vector<BandSpectrum>> spectra;
    for (int listener = 0; listener < 3; ++listener)
        spectra.push_back(bandSpectra(bridgeImpulseResponse(body, rate, 2.0, listener), rate, recipe.bands,
                                      recipe.lossFactor));
    const double radius = std::sqrt(recipe.areaM2 / std::numbers::pi);
    const double apart = 2.0 * std::sin(recipe.sideAngleDegrees * std::numbers::pi / 180.0);
    for (int listener = 1; listener < 3; ++listener)
    {
        const auto levels = measuredBandLevels(spectra[size_t(listener)], recipe.bands, recipe.referenceBand);
        for (size_t b = 0; b < levels.size(); ++b)
        {
            const auto& band = recipe.bands[b];
            INFO(body.listeners[size_t(listener)] << " " << band.lowHz << "-" << band.highHz << " Hz: " << levels[b]
                                                  << " dB, measured " << band.levelDb << " dB");
            if (band.lowHz >= 80.0)
                CHECK(std::abs(levels[b] - band.levelDb) < 1.0);  // each listener fitted (fitBands)
        }
    }
    // Each band's left-right correlation is a sample over its modes of the disc's: within three of
    // its standard errors, (1 - r^2) / sqrt(N - 1) over the band's N effective modes (a band of one or
    // two modes has no such statistic; the lowest bands' sum is checked below).
    int sampled = 0;
    for (size_t b = 0; b < recipe.bands.size(); ++b)
    {
        const auto& band = recipe.bands[b];
        const double disc = directionCorrelation(std::sqrt(band.lowHz * band.highHz), radius, apart);
        const double leftRight = correlationOver(spectra[1], spectra[2], b, b);
        const double n = effectiveModes(body, band);
        INFO(band.lowHz << "-" << band.highHz << " Hz (" << n << " effective modes): left-right " << leftRight
                        << ", the disc's " << disc << "; centre-left " << correlationOver(spectra[0], spectra[1], b, b));
        if (n < 3.0)
            continue;
        ++sampled;
        CHECK(std::abs(leftRight - disc) < 3.0 * (1.0 - disc * disc) / std::sqrt(n - 1.0) + 0.01);
    }
    CHECK(sampled >= 6);  // 800 Hz to 12.5 kHz
    // 50-200 Hz (the disc's 0.96-0.99) and 2-12.5 kHz (below 0.05 in magnitude), each band's modes
    // weighted by their power.
    const double low = correlationOver(spectra[1], spectra[2], 0, 2);
    const double high = correlationOver(spectra[1], spectra[2], 8, recipe.bands.size() - 1);
    INFO("left-right correlation 50-200 Hz " << low << ", 2-12.5 kHz " << high);
    CHECK(low > 0.9);
    CHECK(std::abs(high) < 0.3);
}

TEST_CASE("The tanpura and sitar bodies' mean mobility at the bridge is the infinite plate's, 1/(8 sqrt(D rho h))",
          "[body]")
{
    for (const auto* r : {&tanpuraBodyRecipe(), &sitarBodyRecipe()})
    {
        const auto body = *factoryBody(r->name);
        const double D = r->youngPa * std::pow(r->thicknessM, 3.0) / (12.0 * (1.0 - r->poisson * r->poisson));
        const double plate = 1.0 / (8.0 * std::sqrt(D * r->densityKgM3 * r->thicknessM));
        double sum = 0.0;
        int count = 0;
        for (double f = 1000.0; f < 10000.0; f += 0.5, ++count)
            sum += bodyResponse(body, f).mobilityReal;
        const double mean = sum / count;
        INFO(r->name << ": mean Re Y over 1-10 kHz " << mean << " s/kg, infinite plate " << plate << " s/kg");
        CHECK(mean > 0.9 * plate);
        CHECK(mean < 1.1 * plate);
    }
}

TEST_CASE("Strings and a lossless body conserve their discrete energy to 1e-9 over 1e5 steps; with losses it "
          "never rises",
          "[body][energy]")
{
    for (const char* name : {"tanpura-sa.json", "tanpura-thread.json", "sitar-bridge.json"})
    {
        for (const bool lossless : {true, false})
        {
            Scene scene = withTanpuraBody(test::atPaperConfiguration(test::scene(name)), PickupQuantity::displacement);
            if (lossless)
                makeLossless(scene);
            const auto [result, drift, rise] = referenceEnergy(scene);
            const double H0 = result.stats.initialEnergy;
            INFO(name << (lossless ? " lossless" : " lossy") << ": drift " << drift << ", largest rise " << rise
                      << ", final " << result.energy.back().energy / H0);
            if (lossless)
                CHECK(drift < 1e-9);
            else
            {
                CHECK(rise < 1e-12);
                CHECK(result.energy.back().energy < 0.999 * H0);
            }
        }
    }
}

TEST_CASE("A body whose coupling is zero changes nothing: the string's output bit for bit", "[body]")
{
    const Scene plain = test::scene("tanpura-sa.json");
    Scene uncoupled = withTanpuraBody(plain, PickupQuantity::displacement);
    uncoupled.body->coupling = 0.0;
    const long long steps = 40000;
    RenderOptions projection;
    projection.path = ContactPath::projection;
    const auto a = renderInternal(plain, steps, projection);
    const auto b = renderInternal(uncoupled, steps, projection);
    REQUIRE(a.size() == b.size());
    size_t differing = 0;
    for (size_t n = 0; n < a.size(); ++n)
        differing += a[n] != b[n];
    CHECK(differing == 0);
}

TEST_CASE("Through the tanpura body DAFx-16's C3 string sounds louder over its first half second while its "
          "force on the bridge falls from the pluck (their Fig. 8)",
          "[body]")
{
    Scene scene = test::scene("dafx16-c3-body.json");
    REQUIRE(scene.pickup.quantity == PickupQuantity::pressure);
    const auto pressure = renderScene(scene);
    scene.pickup.quantity = PickupQuantity::bridgeForce;
    const auto force = renderScene(scene);
    const double rate = pressure.outputRateHz;
    const double radiatedPeak = test::envelopePeakSeconds(pressure.output, rate);
    const double forcePeak = test::envelopePeakSeconds(force.output, rate);
    INFO("radiated envelope peaks at " << radiatedPeak << " s, the bridge force's at " << forcePeak << " s");
    CHECK(radiatedPeak > 0.15);
    CHECK(forcePeak < 0.1);
}

TEST_CASE("A scene's body is read and checked, bad input named", "[body][scene]")
{
    const std::string head = R"({"format": "jawari-scene/1",
        "obstacles": [{"type": "point", "position": 0.006, "stiffness": 1e13, "exponent": 1.3}],)";
    const auto scene = parseScene(head + R"("body": {"model": "tanpura", "damping_scale": 0.5},
        "pickup": {"quantity": "pressure"}})");
    REQUIRE(scene.body);
    CHECK(scene.body->obstacles == std::vector<int>{0});
    CHECK(scene.body->body.modes.size() == factoryBody("tanpura")->modes.size());
    CHECK(scene.body->body.modes[3].sigma == Approx(0.5 * factoryBody("tanpura")->modes[3].sigma));
    const auto sitar = parseScene(head + R"("body": {"model": "sitar"}, "pickup": {"quantity": "pressure"}})");
    REQUIRE(sitar.body);
    CHECK(sitar.body->body.name == "sitar");
    CHECK(sitar.body->body.modes.size() == factoryBody("sitar")->modes.size());
    const auto listed = parseScene(head + R"("body": {"modes": [{"frequency": 200, "damping": 3, "mass": 0.2,
        "radiation": 0.01}], "obstacles": [], "coupling": 0.5}})");
    CHECK(listed.body->body.modes.size() == 1);
    CHECK(listed.body->obstacles.empty());
    CHECK(listed.body->coupling == 0.5);
    const auto strung = parseScene(head + R"("body": {"model": "tanpura", "strings": [{"string": {"tension": 90},
        "obstacles": [{"type": "point", "position": 0.006}]}, {"excitation": {"amplitude": 0.001}}]}})");
    REQUIRE(strung.body->strings.size() == 2);
    CHECK(strung.body->strings[0].string.tensionNewtons == 90.0);
    CHECK(strung.body->strings[0].obstacles.size() == 1);
    CHECK(strung.body->strings[0].excitation.amplitude == 0.0);  // at rest without an excitation
    CHECK(strung.body->strings[1].excitation.amplitude == 0.001);

    auto refused = [&](const std::string& tail, const std::string& message) {
        INFO(tail);
        CHECK_THROWS_WITH(parseScene(head + tail), Catch::Contains(message));
    };
    refused(R"("pickup": {"quantity": "pressure"}})", "pickup.quantity: \"pressure\" is the body's radiated sound");
    refused(R"("body": {"model": "guitar"}})", "body.model: unknown value 'guitar'");
    refused(R"("body": {}})", "body: needs either \"model\"");
    refused(R"("body": {"model": "tanpura", "obstacles": [1]}})", "body.obstacles[0]: no obstacle 1");
    refused(R"("body": {"model": "tanpura", "obstacles": [0.5]}})", "body.obstacles[0]: must be an obstacle's index");
    refused(R"("body": {"modes": [{"frequency": 200, "mass": -1}]}})", "body.modes[0].mass: must be > 0");
    refused(R"("body": {"modes": [{"frequency": 200}]}})", "body.modes[0].mass: is required");
    refused(R"("body": {"obstacles": [1e20], "model": "tanpura"}})", "body.obstacles[0]: no obstacle 1e+20");
    // Every number within the range both methods play (ModalBody.h), the range named.
    refused(R"("body": {"modes": [{"frequency": 200, "mass": 0.2, "damping": 1e200}]}})",
            "body.modes[0].damping: must be within [0, 1256.64] /s");
    refused(R"("body": {"modes": [{"frequency": 200, "mass": 0.2}, {"frequency": 2e5, "mass": 0.2}]}})",
            "body.modes[1].frequency: must be within (0, 100000] Hz (got 200000)");
    refused(R"("body": {"modes": [{"frequency": 200, "mass": 1e-300}]}})",
            "body.modes[0].mass: must be within [1e-09, 1e+06] kg");
    refused(R"("body": {"modes": [{"frequency": 200, "mass": 0.2, "radiation": -1e30}]}})",
            "body.modes[0].radiation: must be within +-1e+06 Pa s/m");
    refused(R"("body": {"model": "tanpura", "coupling": 1e12}})", "body.coupling: must be within [0, 100]");
    refused(R"("body": {"model": "tanpura", "damping_scale": 1e308}})",
            "body.damping_scale: must be within [0, 100] for this body");
    refused(R"("body": {"modes": [{"frequency": 200, "mass": 0.2, "damping": 600}], "damping_scale": 3}})",
            "body.damping_scale: must be within [0, 2.0943951");
    refused(R"("body": {"model": "tanpura", "strings": [{"string": {"tension": -1}}]}})",
            "body.strings[0].string.tension: must be > 0");
    refused(R"("body": {"model": "tanpura", "strings": [{"strings": {}}]}})", "body.strings[0].strings: unknown field");
    refused(R"("body": {"model": "tanpura", "strings": [{}]}, "simulation": {"method": "penalty"}})",
            "simulation.method: other strings on the body take the default method");
    refused(R"("body": {"model": "tanpura"}, "pickup": {"quantity": "bridge_force"},
        "simulation": {"method": "realtime"}})", "pickup.quantity: \"bridge_force\" is read by the reference only");
}

TEST_CASE("A scene's body names its listeners and the pressure pickup one of them, bad input named",
          "[body][scene]")
{
    const std::string head = R"({"format": "jawari-scene/1",
        "obstacles": [{"type": "point", "position": 0.006, "stiffness": 1e13, "exponent": 1.3}],)";
    const auto left = parseScene(head + R"("body": {"model": "tanpura"}, "pickup": {"quantity": "pressure",
        "listener": "left"}})");
    CHECK(pickupListener(left) == 1);
    const auto heard = parseScene(head + R"("body": {"listeners": ["front", "side"], "modes": [{"frequency": 200,
        "mass": 0.2, "radiation": [0.01, -0.02]}]}, "pickup": {"quantity": "pressure", "listener": "side"}})");
    CHECK(heard.body->body.listeners == std::vector<std::string>{"front", "side"});
    CHECK(heard.body->body.modes[0].radiation[1] == -0.02);
    CHECK(pickupListener(heard) == 1);

    auto refused = [&](const std::string& tail, const std::string& message) {
        INFO(tail);
        CHECK_THROWS_WITH(parseScene(head + tail), Catch::Contains(message));
    };
    refused(R"("body": {"model": "tanpura"}, "pickup": {"quantity": "pressure", "listener": "behind"}})",
            "pickup.listener: the body has no listener 'behind' (it has 'centre', 'left', 'right')");
    refused(R"("body": {"model": "tanpura"}, "pickup": {"listener": "left"}})",
            "pickup.listener: is where the \"pressure\" pickup hears the body");
    refused(R"("body": {"listeners": ["a", "b"], "modes": [{"frequency": 200, "mass": 0.2, "radiation": 0.01}]}})",
            "body.modes[0].radiation: must be an array of numbers");
    refused(R"("body": {"listeners": ["a", "b"], "modes": [{"frequency": 200, "mass": 0.2, "radiation": [1]}]}})",
            "body.modes[0].radiation: needs one weight per listener (2), got 1");
    refused(R"("body": {"listeners": ["a", "a"], "modes": [{"frequency": 200, "mass": 0.2}]}})",
            "body.listeners[1]: names a listener twice ('a')");
    refused(R"("body": {"listeners": ["a", "b", "c", "d"], "modes": [{"frequency": 200, "mass": 0.2}]}})",
            "body.listeners: must be an array of 1 to 3 names, got 4");
    refused(R"("body": {"model": "tanpura", "listeners": ["a"]}})", "body.listeners: go with \"modes\"");
}

TEST_CASE("The voice with a lossless body conserves its discrete energy to 1e-9 over 1e5 steps", "[body][energy]")
{
    for (const char* name : {"tanpura-sa.json", "tanpura-thread.json", "sitar-bridge.json"})
    {
        Scene scene = withTanpuraBody(test::scene(name), PickupQuantity::pressure);
        scene.simulation.forgetConfiguration();
        setMethodByName(scene.simulation, "realtime");
        makeLossless(scene);
        RenderOptions options;
        options.logEnergy = true;
        scene.simulation.durationSeconds = 1.0;
        const auto probe = renderScene(scene, RenderOptions{});
        // 1e5 internal steps at the voice's rate.
        scene.simulation.durationSeconds = 1e5 / probe.stats.internalRateHz;
        const auto result = renderScene(scene, options);
        const double H0 = result.stats.initialEnergy;
        double drift = 0.0;
        for (const auto& row : result.energy)
            drift = std::max(drift, std::abs(row.energy / H0 - 1.0));
        INFO(name << ": " << result.stats.modes << " modes at " << result.stats.internalRateHz << " Hz, drift " << drift);
        CHECK(result.stats.steps >= 99000);
        CHECK(drift < 1e-9);
    }
}

TEST_CASE("The voice through the tanpura body against the reference, on the preset scenes: at its measured "
          "distance",
          "[body]")
{
    // The radiated sound, LSD and band envelope in dB at the voice's automatic quality: within the
    // quality table's 3 dB (the tanpura's scenes; the sitar's point, which the body's lifted buzz band
    // takes beyond it, within 6 dB until the voice is fixed there), and as measured (docs/measurements.md,
    // "The voice through the body") within 3 %, a regression guard.
    struct Case
    {
        const char* scene;
        double lsd, envelope;
    };
    for (const auto& [name, lsd, envelope] :
         {Case{"tanpura-sa.json", 1.149, 0.243}, Case{"tanpura-pa.json", 1.617, 0.237},
          Case{"tanpura-thread.json", 2.750, 0.565}, Case{"sitar-point.json", 5.181, 0.942}})
    {
        Scene scene = withTanpuraBody(test::scene(name), PickupQuantity::pressure);
        scene.simulation.forgetConfiguration();
        const auto reference = renderScene(scene);
        setMethodByName(scene.simulation, "realtime");
        const auto voice = renderScene(scene);
        const double f0 = scene.string.flexibleFundamentalHz();
        const auto figures = accuracyFigures(lowpass(voice.output, 48000, 20000),
                                             lowpass(reference.output, 48000, 20000), 48000, 10 * f0, 1.0);
        INFO(name << ": voice " << voice.stats.modes << " modes at " << voice.stats.internalRateHz << " Hz, "
                  << voice.stats.cpuSeconds << " CPU s, reference " << reference.stats.cpuSeconds << " CPU s: LSD "
                  << figures.lsd << " dB, envelope " << figures.envelope << " dB, centroid " << figures.centroid
                  << ", relL2 " << figures.relL2);
        CHECK(figures.lsd < (std::string(name) == "sitar-point.json" ? 6.0 : 3.0));
        CHECK(figures.lsd == Approx(lsd).epsilon(0.03));
        CHECK(figures.envelope == Approx(envelope).epsilon(0.03));
    }
}

namespace
{
// tanpura-sa on the tanpura body with `others` more strings on it (tanpura-pa's string and bridge, at
// rest unless `pluckOthers`), the pickup `quantity`, at the paper's configuration.
Scene drone(int others, bool pluckOthers, double coupling = 1.0)
{
    Scene scene = withTanpuraBody(test::scene("tanpura-sa.json"), PickupQuantity::displacement);
    const Scene pa = test::scene("tanpura-pa.json");
    for (int i = 0; i < others; ++i)
    {
        BodyString s{pa.string, pa.obstacles, pa.excitation};
        s.excitation.amplitude = pluckOthers ? pa.excitation.amplitude * (1.0 + 0.1 * i) : 0.0;
        scene.body->strings.push_back(s);
    }
    scene.body->coupling = coupling;
    return scene;
}
}  // namespace

TEST_CASE("Two and four strings on one body: the discrete energy holds to 1e-9 lossless over 1e5 steps, never "
          "rises with losses",
          "[body][energy]")
{
    for (const int strings : {2, 4})
        for (const bool lossless : {true, false})
        {
            Scene scene = drone(strings - 1, true);
            if (lossless)
                makeLossless(scene);
            const auto [result, drift, rise] = referenceEnergy(scene);
            INFO(strings << " strings, " << result.stats.modes << " modes" << (lossless ? ", lossless" : ", lossy")
                         << ": drift " << drift << ", largest rise " << rise);
            CHECK(result.stats.modes == strings * kReferenceModes + int(scene.body->body.modes.size()));
            if (lossless)
                CHECK(drift < 1e-9);
            else
                CHECK(rise < 1e-12);
        }
}

TEST_CASE("The Sitar's string, the body and 13 sympathetic strings: the discrete energy holds to 1e-9 lossless "
          "over 1e5 steps, never rises with losses",
          "[body][energy][sympathetic]")
{
    // sitar-bridge's string on its bridge at 300 modes and 2 MHz (its own converged configuration
    // would take minutes), its sympathetic strings tuned to Kafi from Sa at 138.59 Hz, each on its
    // bridge's spring (SympatheticStrings.h), and then on its jawari too.
    std::vector<double> contactWithout;  // the lossless run's contact energy without the jawari, J
    for (const bool jawari : {false, true})
        for (const bool lossless : {true, false})
        {
            Scene scene = withTanpuraBody(test::scene("sitar-bridge.json"), PickupQuantity::displacement);
            scene.simulation.forgetConfiguration();
            scene.simulation.modes = 300;
            for (int k = 0; k < kMaxSympatheticStrings; ++k)
            {
                const double hz = 138.59 * std::pow(2.0, sympatheticSemitones(k, SympatheticScale::kafi) / 12.0);
                const auto string = sympatheticStringAt(hz);
                scene.body->strings.push_back({string, {sympatheticBridge(string.lengthMetres)}, {}});
                if (jawari)
                    scene.body->strings.back().obstacles.push_back(sympatheticJawari(string.lengthMetres));
                scene.body->strings.back().excitation.amplitude = 0.0;
            }
            if (lossless)
                makeLossless(scene);
            const auto [result, drift, rise] = referenceEnergy(scene);
            INFO(result.stats.modes << " modes" << (jawari ? ", on their jawari" : "")
                                    << (lossless ? ", lossless" : ", lossy") << ": drift " << drift << ", largest rise "
                                    << rise);
            CHECK(result.stats.modes == 14 * 300 + int(scene.body->body.modes.size()));
            if (lossless)
                CHECK(drift < 1e-9);
            else
                CHECK(rise < 1e-12);
            if (!lossless)
                continue;
            // A jawari that no string pressed would leave every force, and so the contact energy, as
            // without it: the largest difference shows that they rang against it.
            double moved = 0.0;
            for (size_t i = 0; i < result.energy.size(); ++i)
                if (!jawari)
                    contactWithout.push_back(result.energy[i].contactEnergy);
                else if (i < contactWithout.size())
                    moved = std::max(moved, std::abs(result.energy[i].contactEnergy - contactWithout[i]));
            if (jawari)
            {
                INFO("the contact energy moved by up to " << moved / result.stats.initialEnergy
                                                          << " of the energy with the jawari");
                CHECK(moved > 1e-7 * result.stats.initialEnergy);
            }
        }
}

TEST_CASE("A string at rest on the body takes energy from a plucked one through it; with no coupling, none", "[body]")
{
    for (const double coupling : {1.0, 0.0})
    {
        auto solver = referenceSolver(drone(1, false, coupling));
        const int M = kReferenceModes;
        const double plucked = modeRangeEnergy(*solver, 0, M);
        double most = 0.0;
        for (int n = 0; n < 200000; ++n)  // 0.1 s
        {
            solver->step();
            if (n % 1000 == 999)
                most = std::max(most, modeRangeEnergy(*solver, M, M));
        }
        INFO("coupling " << coupling << ": the string at rest reached " << most / plucked
                         << " of the plucked string's initial energy");
        if (coupling > 0.0)
            CHECK(most > 1e-6 * plucked);
        else
            CHECK(most == 0.0);
    }
}

TEST_CASE("The voice with a body whose coupling is zero plays the string as without it, to rounding", "[body]")
{
    Scene plain = test::scene("tanpura-sa.json");
    plain.simulation.forgetConfiguration();
    setMethodByName(plain.simulation, "realtime");
    plain.simulation.durationSeconds = 0.3;
    Scene uncoupled = withTanpuraBody(plain, PickupQuantity::displacement);
    uncoupled.body->coupling = 0.0;
    const auto a = renderScene(plain).output;
    const auto b = renderScene(uncoupled).output;
    REQUIRE(a.size() == b.size());
    double peak = 0.0, largest = 0.0;
    for (size_t n = 0; n < a.size(); ++n)
    {
        peak = std::max(peak, std::abs(a[n]));
        largest = std::max(largest, std::abs(a[n] - b[n]));
    }
    INFO("largest difference " << largest << " m of a peak of " << peak << " m");
    CHECK(largest <= 1e-10 * peak);  // rounding: the pluck reaches the modes through the body's map
}

TEST_CASE("Through the body a tanpura string's sound grows after a soft pluck and not after a sharp one: the "
          "pluck, not the bridge, decides",
          "[body]")
{
    // tanpura-sa (a point bridge 6 mm from the end, no thread) pushed by DAFx-16's force pluck, 50 ms
    // over the whole string, and by a 1.5 ms push at the middle, as sharp as the plugin's.
    Scene scene = withTanpuraBody(test::scene("tanpura-sa.json"), PickupQuantity::pressure);
    scene.simulation.durationSeconds = 1.0;
    ForcePluck soft;
    soft.amplitude = -1.0;
    scene.excitation.force = soft;
    scene.excitation.position = soft.position;
    scene.excitation.amplitude = 0.0;  // from rest
    const double softPeak = test::envelopePeakSeconds(renderScene(scene).output, 48000);
    ForcePluck sharp = soft;
    sharp.width = 0.0;
    sharp.duration = 1.5e-3;
    scene.excitation.force = sharp;
    const double sharpPeak = test::envelopePeakSeconds(renderScene(scene).output, 48000);
    INFO("the radiated envelope peaks at " << softPeak << " s after the soft pluck, " << sharpPeak
                                           << " s after the sharp one");
    CHECK(softPeak > 0.3);
    CHECK(sharpPeak < 0.15);
}

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
