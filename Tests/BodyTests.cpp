// Strings and the modal body together (ModalBody.h): their discrete energy, the plugin's strings and
// sympathetic strings among them, the coupling, the voice against the reference through the body,
// and the tanpura heard through it (DAFx-16).

#include "TestSupport.h"

#include "offline/OfflineRender.h"
#include "offline/Scene.h"
#include "physics/body/FactoryBodies.h"
#include "physics/body/ModalBody.h"
#include "physics/body/SharedBody.h"
#include "physics/string/StringDiscretisation.h"
#include "realtime/instrument/VoicePack.h"
#include "realtime/sympathetic/SympatheticStrings.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <complex>
#include <memory>
#include <numbers>

using namespace jawari;

namespace
{
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
// The Sitar's string and bridge with a rigid thread as the plugin plays it (instrumentVoiceConfig: the
// residual compliance, the static pickup above the host's Nyquist frequency, the static-exact forcing),
// four of them retuned to their own pitches and plucked from their shapes, then the 13 sympathetic
// strings at rest, tuned to Kafi from Sa at C#3; every string's damping at 0.
std::vector<std::unique_ptr<Voice>> pluginStringsLossless(const InstrumentStructure& structure)
{
    VoiceConfig played = instrumentVoiceConfig(structure);
    REQUIRE(played.staticExactForcing);
    REQUIRE(played.residualCompliance);
    REQUIRE(played.oversampling > 1);  // the static pickup reads the modes above the host's band
    played.string.damping.law = DampingLaw::none;
    std::vector<std::unique_ptr<Voice>> voices;
    const double ratios[kDroneStrings] = {0.75, 1.0, 1.26, 0.5};
    for (int i = 0; i < kDroneStrings; ++i)
    {
        auto& v = *voices.emplace_back(std::make_unique<Voice>(played));
        const std::vector<double> none(size_t(v.solver().modeCount()), 0.0);
        v.retune(ratios[i], none.data());
        v.pluckFromShape(1.5e-3 * (1.0 + 0.1 * i));
    }
    for (int k = 0; k < kMaxSympatheticStrings; ++k)
    {
        auto c = sympatheticVoiceConfig(instrumentQuality(structure), structure.hostRateHz);
        c.string = sympatheticStringAt(138.59 * std::pow(2.0, sympatheticSemitones(k, SympatheticScale::kafi) / 12.0));
        c.string.damping.law = DampingLaw::none;
        voices.push_back(std::make_unique<Voice>(c));
    }
    return voices;
}

struct LosslessBodyRun
{
    double drift = 0.0;  // the largest |H - H0| / H0, every step or (banked) every chunk
    double taraf = 0.0;  // the sympathetic strings' energy at the end, over H0
    long pressing = 0;   // steps a played string pressed its bridge or thread
    long chunksBanked = 0;
};

// The strings on `body` for 1e5 steps in the instrument's chunks, the sympathetic strings banked for
// each chunk (`banked`) or each in its own solver.
LosslessBodyRun runOnBody(std::vector<ModalSolver*>& solvers, const ModalBody& body, int chunk, bool banked)
{
    SharedBody shared(body, 1.0, solvers[0]->timeStep());
    const int count = int(solvers.size());
    for (int i = 0; i < count; ++i)
        i < kDroneStrings ? shared.check(*solvers[size_t(i)]) : shared.checkLinear(*solvers[size_t(i)]);
    const double H0 = shared.energy(solvers.data(), count);
    auto driftNow = [&] { return std::abs(shared.energy(solvers.data(), count) / H0 - 1.0); };
    LosslessBodyRun run;
    for (long n = 0; n < 100000; n += chunk)
    {
        const bool bank = banked && shared.bankLinear(solvers.data(), kDroneStrings, count);
        run.chunksBanked += bank ? 1 : 0;
        for (int k = 0; k < chunk; ++k)
        {
            shared.step(solvers.data(), count, kDroneStrings);
            bool pressing = false;
            for (int i = 0; i < kDroneStrings; ++i)
                for (int j = 0; j < solvers[size_t(i)]->contactCount(); ++j)
                    pressing = pressing || solvers[size_t(i)]->contactForce(j) != 0.0;
            run.pressing += pressing ? 1 : 0;
            if (!bank)
                run.drift = std::max(run.drift, driftNow());
        }
        if (bank)
            shared.unbankLinear(solvers.data());
        run.drift = std::max(run.drift, driftNow());
    }
    for (int i = kDroneStrings; i < count; ++i)
        run.taraf += solvers[size_t(i)]->stringEnergy() / H0;
    return run;
}
}  // namespace

TEST_CASE("Four strings configured as the plugin's and the 13 sympathetic strings on one body, made lossless, keep "
          "their discrete energy to 1e-9 over 1e5 steps, the sympathetic strings banked as the instrument steps "
          "them or each in its own solver",
          "[sympathetic][body][energy]")
{
    auto structure = test::sitarStructure(kMaxSympatheticStrings);
    structure.thread = true;
    structure.threadModel = ThreadModel::contact;
    structure.bodyDamping = 0.0;  // every body mode's sigma times 0
    const auto body = instrumentBody(structure);
    REQUIRE(body);
    for (const bool banked : {true, false})
    {
        auto voices = pluginStringsLossless(structure);
        std::vector<ModalSolver*> solvers;
        for (auto& v : voices)
            solvers.push_back(&v->solver());
        const auto run = runOnBody(solvers, *body, kChunkSamples * instrumentQuality(structure).oversampling, banked);
        INFO((banked ? "banked" : "each in its own solver") << ": largest |H - H0| / H0 " << run.drift << ", the taraf "
                                                             << run.taraf << " of H0, " << run.pressing
                                                             << " steps a played string pressing, " << run.chunksBanked
                                                             << " chunks banked");
        CHECK(run.drift < 1e-9);
        CHECK(run.pressing > 10000);
        CHECK(run.taraf > 1e-6);  // the body moved them
        CHECK((run.chunksBanked > 0) == banked);
    }
}
