// The voice against the converged reference on a bridge (docs/measurements.md, "The reference's
// convergence on bridges"): sitar-bridge.json names the configuration where the reference stops
// moving (4001 modes, 4 MHz, contact points L/16032 apart), stored in Resources/References since it
// takes about ten CPU minutes a second. The bridge's quality table is measured against it, and so
// is the reference at the paper's configuration, which the faster tests still use.

#include "StoredReference.h"
#include "TestSupport.h"
#include "offline/Analysis.h"
#include "offline/OfflineRender.h"
#include "physics/StringModel.h"
#include "realtime/Quality.h"

#include <catch2/catch.hpp>

#include <string>

using namespace jawari;

namespace
{
// The stored render's FNV-1a over its 32-bit samples: a new render stored means new figures below.
constexpr uint64_t kSitarBridgeHash = 0xb0045451afd9ce6bull;

AccuracyFigures againstConverged(const std::vector<double>& y, const test::StoredReference& converged,
                                 const Scene& scene)
{
    const double buzzFromHz = 10.0 * buildModalTable(scene.string, 1).frequencyHz.front();
    return accuracyFigures(lowpass(y, 48000, 20000), lowpass(converged.samples, 48000, 20000), 48000, buzzFromHz,
                           1.0);
}
}  // namespace

TEST_CASE("the stored converged reference is the sitar-bridge scene's own render", "[.][converged]")
{
    // About ten CPU minutes: run by hand after anything that may move the reference
    // (jawari-plugin-tests "[converged]"). The same build gives the same floats; another rounds differently.
    const auto scene = loadSceneFile(test::resource("Scenes/sitar-bridge.json"));
    const auto rendered = renderScene(scene).output;
    const auto stored = test::storedReference("sitar-bridge");
    REQUIRE(rendered.size() == stored.samples.size());
    const double d = relativeL2(rendered, stored.samples, rendered.size());
    INFO("relL2 against the stored render " << d);
    CHECK(d < 1e-6);
}

TEST_CASE("sitar-bridge against its converged reference: the bridge table's draft, standard and high, and the "
          "reference at the paper's configuration")
{
    const auto scene = loadSceneFile(test::resource("Scenes/sitar-bridge.json"));
    const auto converged = test::storedReference("sitar-bridge");
    INFO("stored render's FNV-1a 0x" << std::hex << converged.fnv1a << std::dec);
    REQUIRE(converged.fnv1a == kSitarBridgeHash);
    REQUIRE(converged.rateHz == 48000.0);
    REQUIRE(converged.samples.size() == 48000);

    // Measured (LSD dB, relL2, envelope dB, centroid): the paper's configuration 2.228, 0.0076,
    // 0.555, 0.0118; draft (103 modes x2) 2.893, 0.0121, 1.068, 0.0157; standard (142 x3) 2.354,
    // 0.0097, 0.671, 0.0118; high (311 x6 on points L/4008) 1.283, 0.0042, 0.287, 0.0069. Each
    // LSD is asserted within 10 %. On the bridge's 23 points 0.9 mm apart (the paper's grid, draft
    // and standard) no voice comes nearer the converged answer than the paper's configuration is;
    // high's points four times finer do (on the 23 points, 311 modes at 16x were 2.26 dB away).
    const auto paper = againstConverged(renderScene(test::atPaperConfiguration(scene)).output, converged, scene);
    INFO("the paper's configuration: LSD " << paper.lsd << " dB, relL2 " << paper.relL2 << ", envelope "
                                           << paper.envelope << " dB, centroid " << paper.centroid);
    CHECK(paper.lsd == Approx(2.228).epsilon(0.1));
    struct Setting
    {
        const char* name;
        double lsd;
    };
    AccuracyFigures at[3];
    const Setting settings[] = {{"draft", 2.893}, {"standard", 2.354}, {"high", 1.283}};
    for (size_t k = 0; k < 3; ++k)
    {
        const auto q = resolveQuality(*qualityByName(settings[k].name, ObstacleKind::bridge), scene.string, 48000.0);
        auto voice = scene;
        voice.simulation.reference = false;
        voice.simulation.modes = q.modes;
        voice.simulation.rateHz = q.oversampling * 48000.0;
        if (q.contactIntervals > 0)  // the bridge's points as the plugin lays them at this quality
            voice.obstacles.front().spacing = scene.string.lengthMetres / q.contactIntervals;
        at[k] = againstConverged(renderScene(voice).output, converged, scene);
        INFO(settings[k].name << " (" << q.modes << " modes x" << q.oversampling << "): LSD " << at[k].lsd
                              << " dB, relL2 " << at[k].relL2 << ", envelope " << at[k].envelope << " dB, centroid "
                              << at[k].centroid);
        CHECK(at[k].lsd == Approx(settings[k].lsd).epsilon(0.1));
    }
    // The Sitar preset's bound at standard (the plugin's tests: 3 dB), and its buzz band followed.
    CHECK(at[1].lsd < 3.0);
    CHECK(at[1].envelope < 1.0);
    CHECK(at[1].centroid < 0.03);
    CHECK(at[2].lsd < at[1].lsd);
    CHECK(at[2].lsd < paper.lsd - 0.5);
    CHECK(at[1].lsd < at[0].lsd);
}
