// The accuracy measures converge (docs/design.md section 4): the voice at the reference's own modes
// and rate, against the reference and against the reference's own floor (the reference under a 1e-4
// change of the pluck), on every preset scene; and the distributed bridge's answer moves far less
// with the modes kept on its own contact points than on the mode grid.

#include "TestSupport.h"
#include "offline/Analysis.h"
#include "offline/OfflineRender.h"
#include "realtime/voice/Quality.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <string>

using namespace jawari;

namespace
{
// Every measure of y against ref over the first `seconds` (relL2 over 100 ms), both low-passed at
// 20 kHz, the buzz band from the scene string's 10th partial.
AccuracyFigures measure(const RenderResult& y, const RenderResult& ref, const Scene& scene, double seconds)
{
    const double buzzFromHz = 10.0 * buildModalTable(scene.string, 1).frequencyHz.front();
    return accuracyFigures(lowpass(y.output, 48000, 20000), lowpass(ref.output, 48000, 20000), 48000, buzzFromHz,
                           seconds);
}
}  // namespace

namespace
{
// The voice at the reference's modes and rate against the reference, measured over 0.3 s: relL2, LSD
// (dB) and the centroid track's distance. Their ratios to the floor: relL2 0.3x (paper-tanpura) to
// 17x (bass-frets), LSD 0.016x (free-string) to 46x (tanpura-sa).
struct VoiceDistance
{
    const char* scene;
    double relL2, lsd, centroid;
};
constexpr VoiceDistance kVoiceDistances[] = {
    {"paper-centre", 9.375e-4, 0.01733, 1.557e-6},  {"paper-tanpura", 2.998e-5, 9.139e-5, 4.363e-8},
    {"tanpura-sa", 1.563e-3, 0.03257, 1.207e-6},    {"tanpura-pa", 4.975e-4, 6.717e-3, 1.439e-7},
    {"sitar-bridge", 2.203e-4, 7.983e-4, 4.787e-7}, {"bass-frets", 3.065e-3, 0.05519, 1.995e-4},
    {"free-string", 1.185e-4, 7.515e-6, 4.060e-8}};
constexpr double kDistanceTolerance = 0.25;
}  // namespace

TEST_CASE("the voice at the reference's modes and rate: its envelope within the reference's own floor, its "
          "waveform and spectrum at their measured distances (up to 17x and 46x the floor) on every preset scene")
{
    const double seconds = 0.3;
    for (const auto& expected : kVoiceDistances)
    {
        const char* name = expected.scene;
        auto scene = test::atPaperConfiguration(test::scene(std::string(name) + ".json"));
        scene.simulation.durationSeconds = seconds;
        scene.simulation.rateHz = 42 * 48000.0;  // 2.016 MHz: the reference's rate, a whole multiple for the voice
        // The voice (1001 modes, nothing dropped) and the reference, and the reference against itself
        // with the pluck raised by 1e-4 (the floor).
        auto voiceOf = [](Scene s) {
            s.simulation.reference = false;
            s.simulation.modes = kReferenceModes;
            s.simulation.residualCompliance = false;
            return renderScene(s);
        };
        const auto reference = renderScene(scene);
        auto perturbed = scene;
        perturbed.excitation.amplitude *= 1.0 + 1e-4;
        const auto floor = measure(renderScene(perturbed), reference, scene, seconds);
        const auto voice = measure(voiceOf(scene), reference, scene, seconds);
        // What the two output filters (the voice's decimator, the reference's resampler) make of the
        // same string without its obstacles: both exact there, so this is the filters' own difference,
        // most of the voice's distance where the buzz puts the sound near 20 kHz (tanpura-sa, bass-frets).
        auto free = scene;
        free.obstacles.clear();
        const auto filters = measure(voiceOf(free), renderScene(free), free, seconds);
        INFO(name << ": relL2 " << voice.relL2 << " (measured " << expected.relL2 << " +-25 % binds; floor "
                  << floor.relL2 << ", " << voice.relL2 / floor.relL2 << "x; filters " << filters.relL2 << "); LSD "
                  << voice.lsd << " dB (measured " << expected.lsd << " +-25 % binds; floor " << floor.lsd << ", "
                  << voice.lsd / floor.lsd << "x; filters " << filters.lsd << "); envelope " << voice.envelope
                  << " dB (the floor " << floor.envelope << " binds); centroid " << voice.centroid << " (measured "
                  << expected.centroid << " +25 % binds; floor " << floor.centroid << ")");
        CHECK(voice.relL2 == Approx(expected.relL2).epsilon(kDistanceTolerance));
        CHECK(voice.lsd == Approx(expected.lsd).epsilon(kDistanceTolerance));
        CHECK(voice.envelope <= floor.envelope);
        // The centroid tracks agree to 2e-4 at most (bass-frets): bounded from above only.
        CHECK(voice.centroid <= (1.0 + kDistanceTolerance) * expected.centroid);
    }
}

TEST_CASE("a bridge's contact points are its own: from 197 to 260 modes the voice moves 1.4 dB, a fifth of its move "
          "with the bridge on the mode grid")
{
    const double seconds = 0.5;
    auto scene = test::atPaperConfiguration(test::scene("sitar-bridge.json"));
    scene.simulation.durationSeconds = seconds;
    const double L = scene.string.lengthMetres;
    // The voice at standard's rate with 197 and 260 modes, the bridge on its fixed points and, for
    // comparison, on each voice's own mode grid (the points move with M).
    auto voiceWith = [&](int modes, bool onModeGrid) {
        auto v = scene;
        v.simulation.reference = false;
        v.simulation.modes = modes;
        v.simulation.rateHz = 6 * 48000.0;
        if (onModeGrid)
            v.obstacles.front().spacing = L / (modes + 1);
        return lowpass(renderScene(v).output, 48000, 20000);
    };
    const double fixedChange = logSpectralDistance(voiceWith(197, false), voiceWith(260, false), 48000, seconds);
    const double gridChange = logSpectralDistance(voiceWith(197, true), voiceWith(260, true), 48000, seconds);
    // The reference with its bridge sampled every 1, 2 and 4 nodes of its grid (0.9, 1.8, 3.6 mm).
    auto referenceEvery = [&](int nodes) {
        auto r = scene;
        r.obstacles.front().spacing = nodes * L / (kReferenceModes + 1);
        return lowpass(renderScene(r).output, 48000, 20000);
    };
    const auto fine = referenceEvery(1);
    const double twice = logSpectralDistance(referenceEvery(2), fine, 48000, seconds);
    const double fourTimes = logSpectralDistance(referenceEvery(4), fine, 48000, seconds);
    INFO("LSD 197 -> 260 modes: fixed points " << fixedChange << " dB, on the mode grid " << gridChange
                                                << " dB; reference at 1.8 mm against 0.9 mm " << twice
                                                << " dB, at 3.6 mm " << fourTimes << " dB");
    // Measured 1.44 dB against 7.49 dB (0.19x), each asserted within 25 %: the answer still moves
    // with M on fixed points, by far less than on the mode grid.
    CHECK(fixedChange == Approx(1.44).epsilon(0.25));
    CHECK(gridChange == Approx(7.49).epsilon(0.25));
    CHECK(fixedChange < 0.25 * gridChange);
    // At the paper's configuration the reference is not converged in the spacing (it converges at
    // L/16032 with 4001 modes at 4 MHz, the scene's own configuration: docs/measurements.md), so
    // this only states that coarser is further away.
    CHECK(twice < fourTimes);
}

TEST_CASE("reading the modes above Nyquist statically moves the voice far less than its distance from the reference")
{
    const double seconds = 0.5;
    // The preset scenes read displacement; paper-tanpura also reads velocity and the force on the
    // termination.
    struct Case
    {
        const char* name;
        PickupQuantity quantity;
    };
    for (const auto [name, quantity] : {Case{"paper-centre", PickupQuantity::displacement},
                                        Case{"paper-tanpura", PickupQuantity::displacement},
                                        Case{"paper-tanpura", PickupQuantity::velocity},
                                        Case{"paper-tanpura", PickupQuantity::force},
                                        Case{"tanpura-sa", PickupQuantity::displacement},
                                        Case{"sitar-bridge", PickupQuantity::displacement},
                                        Case{"bass-frets", PickupQuantity::displacement}})
        for (const char* quality : {"standard", "high"})
        {
            auto scene = test::atPaperConfiguration(test::scene(std::string(name) + ".json"));
            scene.pickup.quantity = quantity;
            scene.simulation.durationSeconds = seconds;
            const auto reference = renderScene(scene);
            const bool bridge = std::any_of(scene.obstacles.begin(), scene.obstacles.end(),
                                            [](const Obstacle& o) { return o.isDistributed(); });
            const auto kind = bridge ? ObstacleKind::bridge : ObstacleKind::points;
            const auto q = resolveQuality(*qualityByName(quality, kind), scene.string, 48000.0);
            auto voice = scene;
            voice.simulation.reference = false;
            voice.simulation.modes = q.modes;
            voice.simulation.rateHz = q.oversampling * 48000.0;
            auto everyMode = voice;
            everyMode.simulation.staticPickup = false;
            const auto readStatically = renderScene(voice);
            const auto readMoving = renderScene(everyMode);
            const auto change = measure(readStatically, readMoving, scene, seconds);
            const auto moving = measure(readMoving, reference, scene, seconds);
            const auto statically = measure(readStatically, reference, scene, seconds);
            INFO(name << " (" << quantityName(quantity) << ") at " << quality << " (" << q.modes << " modes x" << q.oversampling << "): static against moving relL2 "
                      << change.relL2 << " LSD " << change.lsd << " dB; against the reference, moving LSD " << moving.lsd
                      << " dB relL2 " << moving.relL2 << ", static LSD " << statically.lsd << " dB relL2 "
                      << statically.relL2);
            // Displacement and velocity, measured: at most relL2 7.4e-6 and LSD 0.0024 dB, 0.1 % of
            // the distance to the reference. With the modes above the band simply left out (no static
            // response) this fails: tanpura-sa at standard relL2 6.4e-5, the force 0.05 to 0.20. The force on the termination weights each mode by its number, so
            // the modes read statically carry more of it: relL2 1.4e-3 (0.7 % of the distance) and
            // LSD 0.36 dB, and the static reading is the closer of the two to the reference.
            const bool force = quantity == PickupQuantity::force;
            CHECK(change.lsd < (force ? 0.15 : 0.01) * moving.lsd);
            CHECK(change.relL2 < (force ? 0.02 : 0.01) * moving.relL2);
            CHECK(statically.lsd < moving.lsd + 0.01);
        }
}
