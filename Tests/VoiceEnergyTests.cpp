// The real-time voice's energy: conserved where nothing is lost (every scene made lossless, the
// quadratised method in contact), never gained where something is (the residual compliance as
// backward Euler, the damped thread), and the residual compliance keeping the dropped modes' part.

#include "TestSupport.h"
#include "offline/Analysis.h"
#include "offline/AutomaticQuality.h"
#include "offline/OfflineRender.h"
#include "realtime/voice/Voice.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace jawari;


TEST_CASE("the quadratised method conserves its energy while in contact and never gains any (no losses)")
{
    auto scene = test::scene("paper-centre.json");
    scene.string.damping.law = DampingLaw::none;
    auto config = test::voiceFor(scene, 200, 8, 48000.0);
    config.method = ContactMethod::quadratised;
    config.residualCompliance = false;
    Voice voice(config);
    voice.setInitialShape(0.501, 1.5e-3);
    const double H0 = voice.solver().energy().total;
    double previous = H0, worstIncrease = 0.0, worstInContact = 0.0;
    long contactSteps = 0;
    bool touching = false;  // u^n penetrates: this step's force comes from V(u^n) > 0
    for (int n = 0; n < 8 * 9600; ++n)
    {
        voice.solver().step();
        const double H = voice.solver().energy().total;
        worstIncrease = std::max(worstIncrease, (H - previous) / H0);
        // A step taken in contact conserves the quadratised energy exactly; a step out of contact
        // releases the auxiliary variable (xi = sqrt(2 V) = 0 there), which can only lower it.
        if (touching)
        {
            worstInContact = std::max(worstInContact, std::abs(H - previous) / H0);
            ++contactSteps;
        }
        previous = H;
        touching = voice.solver().lastMaxPenetration() > 0.0;
    }
    INFO("largest step increase " << worstIncrease << ", largest change within a contact " << worstInContact << " over "
                                  << contactSteps << " steps, H(200 ms)/H(0) " << previous / H0);
    CHECK(contactSteps > 1000);
    CHECK(worstIncrease <= 1e-12);
    CHECK(worstInContact < 1e-12);
}

TEST_CASE("with the residual compliance as backward Euler (theta = 1) the energy only ever decreases (lossless string)")
{
    auto scene = test::scene("paper-tanpura.json");
    scene.string.damping.law = DampingLaw::none;
    for (auto method : {ContactMethod::energyConserving, ContactMethod::quadratised})
    {
        auto config = test::voiceFor(scene, 150, 8, 48000.0);
        config.method = method;
        config.residualComplianceLoss = 1.0;
        Voice voice(config);
        voice.setInitialShape(0.501, 1.5e-3);
        double previous = voice.solver().energy().total;
        const double H0 = previous;
        double worstIncrease = 0.0;
        std::vector<double> y(1);
        for (int m = 0; m < 9600; ++m)
        {
            voice.process(y.data(), 1);
            const double H = voice.solver().energy().total;
            worstIncrease = std::max(worstIncrease, (H - previous) / H0);
            previous = H;
        }
        INFO("method " << int(method) << ": largest step increase " << worstIncrease << ", H(200 ms)/H(0) "
                       << previous / H0);
        CHECK(worstIncrease <= 1e-12);
        CHECK(previous < 0.95 * H0);  // the spring's loss: 0.925 of H0 is left
    }
}

namespace
{
struct LosslessRun
{
    double drift = 0.0;          // the largest |H - H0| / H0 over the energy log
    double peakContactEnergy = 0.0;  // J: the contact and its spring held some, so they were tested
    double largestRise = 0.0;        // the largest H - H_previous between rows, over H0
    double finalEnergy = 0.0;        // the last row's H over H0
};

// A scene's voice made lossless (a damped thread's damper too, unless kept), over its energy log (one
// value a sample) for at least `steps` internal steps. A force pluck becomes the voice's triangle.
LosslessRun losslessVoiceRun(Scene scene, bool residualCompliance, long steps, bool keepThreadDamper = false,
                             bool staticExactForcing = false)
{
    scene.string.damping.law = DampingLaw::none;
    if (!keepThreadDamper)
        for (auto& o : scene.obstacles)
            o.law.damping = 0.0;  // a damped thread's damper
    if (scene.excitation.force)
    {
        scene.excitation.force.reset();  // the voice plucks
        scene.excitation.amplitude = 1.5e-3;
    }
    scene.simulation.reference = false;
    scene.simulation.contact = ContactMethod::energyConserving;
    scene.simulation.forgetConfiguration();
    scene.simulation.residualCompliance = residualCompliance;
    scene.simulation.staticExactForcing = staticExactForcing;
    const auto quality = automaticQuality(scene);
    scene.simulation.durationSeconds = double(steps + 2 * quality.oversampling)
                                       / (quality.oversampling * scene.simulation.outputRateHz);
    RenderOptions options;
    options.logEnergy = true;
    const auto result = renderScene(scene, options);
    const double H0 = result.stats.initialEnergy;
    LosslessRun run;
    double previous = H0;
    for (const auto& e : result.energy)
    {
        const double drift = std::abs(e.energy - H0) / H0;
        if (!(drift <= run.drift))  // a NaN is kept, and fails the caller's check
            run.drift = drift;
        run.peakContactEnergy = std::max(run.peakContactEnergy, e.contactEnergy);
        run.largestRise = std::max(run.largestRise, (e.energy - previous) / H0);
        previous = e.energy;
    }
    run.finalEnergy = previous / H0;
    return run;
}
}  // namespace

TEST_CASE("every scene made lossless keeps its voice's energy to 1e-9 over 1e5 steps, with and without the "
          "residual compliance")
{
    for (const char* name : {"bass-frets.json", "dafx16-c3.json", "free-string.json", "paper-centre.json",
                             "paper-tanpura.json", "sitar-bridge.json", "sitar-point.json", "tanpura-pa.json",
                             "tanpura-sa.json", "tanpura-thread.json"})
        for (bool compliance : {true, false})
        {
            const auto run = losslessVoiceRun(test::scene(name), compliance, 100000);
            INFO(name << (compliance ? " with" : " without") << " the residual compliance: largest |H - H0| / H0 "
                      << run.drift << ", peak contact energy " << run.peakContactEnergy << " J");
            CHECK(run.drift < 1e-9);
            if (std::string(name) != "free-string.json")
                CHECK(run.peakContactEnergy > 0.0);
        }
    // The thread's strings as the plugin plays them, with the static-exact forcing (VoicePack.cpp).
    for (bool compliance : {true, false})
    {
        const auto run = losslessVoiceRun(test::scene("tanpura-thread.json"), compliance, 100000, false, true);
        INFO("tanpura-thread with the static-exact forcing,"
             << (compliance ? " with" : " without") << " the residual compliance: largest |H - H0| / H0 " << run.drift);
        CHECK(run.drift < 1e-9);
        CHECK(run.peakContactEnergy > 0.0);
    }
}

TEST_CASE("the residual compliance keeps what dropped modes that hardly decay would give back: DAFx-16's string at a "
          "constant damping keeps its buzz band as the reference does")
{
    // DAFx-16's C3 string on its flat bridge, no thread, the triangular pluck, every mode at 0.6 /s:
    // the energy the bridge pushes into the dropped modes rings there and comes back. Its centroid
    // from the 10th partial to 16 kHz, 0.9-1.1 s over 0.1-0.3 s (100 ms frames).
    auto scene = test::scene("dafx16-c3.json");
    scene.obstacles.pop_back();  // the thread
    scene.excitation.force.reset();
    scene.excitation.amplitude = 1.5e-3;
    scene.string.damping.law = DampingLaw::constant;
    scene.string.damping.sigma = 0.6;
    const double reference = test::centroidFall(renderScene(scene).output, 44100.0);
    scene.simulation.reference = false;
    scene.simulation.modes = 133;
    scene.simulation.rateHz = 8 * 44100.0;
    const double voice = test::centroidFall(renderScene(scene).output, 44100.0);
    INFO("centroid late / early: reference " << reference << ", voice " << voice);
    CHECK(reference > 0.95);  // measured 1.004
    // Measured 0.914; with theta = 1 it falls to 0.562, with theta = 0 the spring's ringing lifts it to 1.671.
    CHECK(voice > 0.8);
    CHECK(voice < 1.2);
}

TEST_CASE("the voice of DAFx-16's string with its damped thread: the damper only ever takes energy", "[thread]")
{
    const auto scene = test::scene("dafx16-c3.json");
    for (bool compliance : {true, false})
    {
        const auto run = losslessVoiceRun(scene, compliance, 100000, true);
        INFO((compliance ? "with" : "without") << " the residual compliance: largest rise " << run.largestRise
                                               << " of H0, left " << run.finalEnergy << " of H0");
        CHECK(run.largestRise <= 1e-12);
        CHECK(run.finalEnergy < 0.999);  // the damper took some (the string itself is lossless)
    }
}
