// The voice against the converged reference on a bridge (docs/measurements.md, "The reference's
// convergence on bridges"): sitar-bridge.json names the configuration where the reference stops
// moving (4001 modes, 4 MHz, contact points L/16032 apart), tanpura-thread.json the point contacts'
// (2003 modes at 16 MHz with the rate extrapolated, its bridge's points L/16032 apart), and
// parabola-bridge.json the static-exact forcing's (2003 modes, 2 MHz, points L/16032 apart), each
// stored in Resources/References since it takes half a minute to nine CPU minutes a second. The bridge's quality
// table is measured against them, and so is the reference at the paper's configuration, which the
// faster tests still use.

#include "StoredReference.h"
#include "TestSupport.h"
#include "offline/Analysis.h"
#include "offline/OfflineRender.h"
#include "physics/string/StringModel.h"
#include "realtime/voice/Quality.h"

#include <catch2/catch.hpp>

#include <array>
#include <string>

using namespace jawari;

namespace
{
// The stored renders' FNV-1a over their 32-bit samples: a new render stored means new figures below.
constexpr uint64_t kSitarBridgeHash = 0xb0045451afd9ce6bull;
constexpr uint64_t kTanpuraThreadHash = 0x3e0bd98f8264fe13ull;
constexpr uint64_t kParabolaBridgeHash = 0x9a0da5833476d437ull;

AccuracyFigures againstConverged(const std::vector<double>& y, const test::StoredReference& converged,
                                 const Scene& scene)
{
    const double buzzFromHz = 10.0 * buildModalTable(scene.string, 1).frequencyHz.front();
    return accuracyFigures(lowpass(y, 48000, 20000), lowpass(converged.samples, 48000, 20000), 48000, buzzFromHz,
                           1.0);
}

// The scene rendered again matches its stored render: the same build gives the same floats, another
// rounds differently.
void checkStoredIsRender(const std::string& name)
{
    const auto scene = test::scene(name + ".json");
    const auto rendered = renderScene(scene).output;
    const auto stored = test::storedReference(name);
    REQUIRE(rendered.size() == stored.samples.size());
    const double d = relativeL2(rendered, stored.samples, rendered.size());
    INFO(name << ": relL2 against the stored render " << d);
    CHECK(d < 1e-6);
}
}  // namespace

// About nine, three and half a CPU minute (machine F): parabola-bridge's, the cheapest, runs with every
// test; the other two by hand after anything that may move the reference (jawari-plugin-tests
// "[converged]", docs/validation.md).
TEST_CASE("the stored converged reference is the sitar-bridge scene's own render", "[.][converged]")
{
    checkStoredIsRender("sitar-bridge");
}

TEST_CASE("the stored converged reference is the tanpura-thread scene's own render", "[.][converged]")
{
    checkStoredIsRender("tanpura-thread");
}

TEST_CASE("the stored converged reference is the parabola-bridge scene's own render", "[converged]")
{
    checkStoredIsRender("parabola-bridge");
}

namespace
{
// The scene at the paper's configuration and the voice at the bridge table's draft, standard and high,
// each against the stored converged reference (LSD dB, relL2, envelope dB, centroid), printed.
struct BridgeTableFigures
{
    AccuracyFigures paper;
    AccuracyFigures at[3];
};

BridgeTableFigures bridgeTableFigures(const Scene& scene, const test::StoredReference& converged, bool staticExactVoice)
{
    BridgeTableFigures f;
    f.paper = againstConverged(renderScene(test::atPaperConfiguration(scene)).output, converged, scene);
    const char* names[] = {"draft", "standard", "high"};
    for (size_t k = 0; k < 3; ++k)
    {
        const auto q = resolveQuality(*qualityByName(names[k], ObstacleKind::bridge), scene.string, 48000.0);
        auto voice = scene;
        voice.simulation.reference = false;
        voice.simulation.forgetConfiguration();
        voice.simulation.staticExactForcing = staticExactVoice;
        voice.simulation.modes = q.modes;
        voice.simulation.rateHz = q.oversampling * 48000.0;
        if (q.contactIntervals > 0)  // the bridge's points as the plugin lays them at this quality
            voice.obstacles.front().spacing = scene.string.lengthMetres / q.contactIntervals;
        f.at[k] = againstConverged(renderScene(voice).output, converged, scene);
        UNSCOPED_INFO(names[k] << " (" << q.modes << " modes x" << q.oversampling << "): LSD " << f.at[k].lsd
                               << " dB, relL2 " << f.at[k].relL2 << ", envelope " << f.at[k].envelope
                               << " dB, centroid " << f.at[k].centroid);
    }
    UNSCOPED_INFO("the paper's configuration: LSD " << f.paper.lsd << " dB, relL2 " << f.paper.relL2 << ", envelope "
                                                    << f.paper.envelope << " dB, centroid " << f.paper.centroid);
    return f;
}

test::StoredReference checkedStored(const std::string& name, uint64_t hash)
{
    const auto converged = test::storedReference(name);
    INFO(name << ": stored render's FNV-1a 0x" << std::hex << converged.fnv1a << std::dec);
    REQUIRE(converged.fnv1a == hash);
    REQUIRE(converged.rateHz == 48000.0);
    REQUIRE(converged.samples.size() == 48000);
    return converged;
}

// The scene's bridge table against its stored converged reference: each LSD within 10 % of what was
// measured (the paper's configuration, then draft, standard and high), the table in order (high
// nearer than standard, standard nearer than draft), and standard within the preset's bound. The
// voice takes the static-exact forcing where the plugin's does (a rigid thread: VoicePack.cpp).
BridgeTableFigures checkBridgeTable(const std::string& name, uint64_t hash, double paper,
                                    const std::array<double, 3>& measured, double standardBound,
                                    bool staticExactVoice = false)
{
    const auto scene = test::scene(name + ".json");
    const auto f = bridgeTableFigures(scene, checkedStored(name, hash), staticExactVoice);
    CHECK(f.paper.lsd == Approx(paper).epsilon(0.1));
    for (size_t k = 0; k < 3; ++k)
        CHECK(f.at[k].lsd == Approx(measured[k]).epsilon(0.1));
    CHECK(f.at[2].lsd < f.at[1].lsd);
    CHECK(f.at[1].lsd < f.at[0].lsd);
    CHECK(f.at[1].lsd < standardBound);
    return f;
}
}  // namespace

TEST_CASE("sitar-bridge against its converged reference: the bridge table's draft, standard and high, and the "
          "reference at the paper's configuration")
{
    // Measured (LSD dB, relL2, envelope dB, centroid): the paper's configuration 2.228, 0.0076,
    // 0.555, 0.0118; draft (103 modes x2) 2.893, 0.0121, 1.068, 0.0157; standard (142 x3) 2.354,
    // 0.0097, 0.671, 0.0118; high (311 x6 on points L/4008) 1.283, 0.0042, 0.287, 0.0069. Each
    // LSD is asserted within 10 %. On the bridge's 23 points 0.9 mm apart (the paper's grid, draft
    // and standard) no voice comes nearer the converged answer than the paper's configuration is;
    // high's points four times finer do (on the 23 points, 311 modes at 16x were 2.26 dB away).
    // The Sitar preset's bound at standard is the plugin's tests' 3 dB; its buzz band is followed.
    const auto f = checkBridgeTable("sitar-bridge", kSitarBridgeHash, 2.228, {2.893, 2.354, 1.283}, 3.0);
    CHECK(f.at[1].envelope < 1.0);
    CHECK(f.at[1].centroid < 0.03);
    CHECK(f.at[2].lsd < f.paper.lsd - 0.5);
}

TEST_CASE("tanpura-thread against its converged reference: the bridge table's draft, standard and high, and the "
          "reference at the paper's configuration")
{
    // Measured (LSD dB, relL2): the paper's configuration 0.640, 0.0022; with the static-exact
    // forcing the plugin gives a rigid thread, draft (2 x 110 modes x2) 4.112, 0.0239; standard (2 x
    // 149 x3) 2.911, 0.0120; high (2 x 302 x6) 1.960, 0.0014 (with the paper's gain 4.846, 3.608 and
    // 2.460). The Tanpura thread preset's bound at standard is the plugin's tests' 3 dB.
    checkBridgeTable("tanpura-thread", kTanpuraThreadHash, 0.640, {4.112, 2.911, 1.960}, 3.0, true);
}

TEST_CASE("parabola-bridge against its converged reference: the bridge table's draft, standard and high, and the "
          "reference at the paper's configuration")
{
    // Measured (LSD dB, relL2): the paper's configuration 4.867, 0.0188; draft (110 modes x2) 6.786,
    // 0.0828; standard (149 x3) 6.340, 0.0593; high (302 x6) 4.773, 0.0331. No preset plays this
    // bridge (1e13 N/m^1.3 pressed at 0.4 L, wrapped over 0.3 mm): its converged answer needs points
    // L/16032 apart, where the voice keeps the bridge's 20 points L/1002 apart, so the table is
    // recorded here (each LSD within 10 %), with the standard's bound at that measure plus 10 %.
    checkBridgeTable("parabola-bridge", kParabolaBridgeHash, 4.867, {6.786, 6.340, 4.773}, 7.0);
}

namespace
{
// The scene's reference with the static-exact forcing at (2003 modes, 2 MHz), its points as the
// scene gives them (L/16032), over `seconds`.
std::vector<double> staticExactAt2003(const std::string& name, double seconds)
{
    auto scene = test::scene(name + ".json");
    scene.simulation.modes = 2003;
    scene.simulation.rateHz = 2e6;
    scene.simulation.extrapolateRate = false;
    scene.simulation.staticExactForcing = true;
    scene.simulation.durationSeconds = seconds;
    return renderScene(scene).output;
}
}  // namespace

TEST_CASE("the static-exact forcing at 2003 modes and 2 MHz meets the stored converged references: tanpura-thread "
          "over its whole second, sitar-bridge over its first 100 ms")
{
    // The stored renders take the paper's forcing at (2003, 16 MHz) extrapolated and (4001, 4 MHz);
    // the static-exact forcing settles from (2003, 2 MHz) (docs/measurements.md, "The static-exact
    // forcing"). Measured: tanpura-thread 0.180 dB and relL2 1.6e-4 over 1 s (0.157 dB at (4001,
    // 4 MHz)), sitar-bridge 0.037 dB and relL2 3.3e-4 over 100 ms. About 27 CPU s.
    const auto threadScene = test::scene("tanpura-thread.json");
    const auto thread = againstConverged(staticExactAt2003("tanpura-thread", 1.0),
                                         checkedStored("tanpura-thread", kTanpuraThreadHash), threadScene);
    const auto sitarStored = checkedStored("sitar-bridge", kSitarBridgeHash);
    const auto sitar = lowpass(staticExactAt2003("sitar-bridge", 0.1), 48000, 20000);
    const std::vector<double> sitarFirst(sitarStored.samples.begin(), sitarStored.samples.begin() + 4800);
    const auto stored = lowpass(sitarFirst, 48000, 20000);
    const double sitarL2 = relativeL2(sitar, stored, stored.size());
    const double sitarLsd = logSpectralDistance(sitar, stored, 48000, 0.1, 20000.0, 80.0, 2048);
    INFO("tanpura-thread over 1 s: LSD " << thread.lsd << " dB, relL2 " << thread.relL2
                                         << "; sitar-bridge over 100 ms: "
                                         << "LSD " << sitarLsd << " dB, relL2 " << sitarL2);
    CHECK(thread.lsd < 0.3);
    CHECK(thread.relL2 < 1e-3);
    CHECK(sitarLsd < 0.3);
    CHECK(sitarL2 < 1e-3);
}
