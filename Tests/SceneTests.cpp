// jawari-scene/1 (docs/scenes.md): defaults, the paper scenes, and bad scenes rejected with
// the field named.

#include "TestSupport.h"
#include "offline/Scene.h"

#include <catch2/catch.hpp>

#include <string>
#include <utility>
#include <vector>

using namespace jawari;

TEST_CASE("a scene with only its format gets the paper's defaults")
{
    const auto s = parseScene(R"({"format": "jawari-scene/1"})");
    CHECK(s.string.lengthMetres == 1.002);
    CHECK(s.string.tensionNewtons == 180.5);
    CHECK(s.string.damping.law == DampingLaw::valette);
    CHECK(s.obstacles.empty());
    CHECK(s.excitation.position == 0.501);
    CHECK(s.pickup.position == 0.992);
    CHECK(s.simulation.reference);
    CHECK_FALSE(s.simulation.rateHz.has_value());
    CHECK(s.simulation.outputRateHz == 48000);
}

TEST_CASE("the paper scenes load with their exact parameters")
{
    const auto centre = test::scene("paper-centre.json");
    REQUIRE(centre.obstacles.size() == 1);
    CHECK(centre.obstacles[0].position == 0.501);
    CHECK(centre.obstacles[0].law.stiffness == 1e13);
    CHECK(centre.obstacles[0].law.exponent == 1.3);
    CHECK(*centre.simulation.rateHz == 2e6);
    CHECK(*centre.simulation.modes == 1001);
    const auto tanpura = test::scene("paper-tanpura.json");
    CHECK(tanpura.obstacles[0].position == 0.006);
    CHECK_FALSE(tanpura.simulation.extrapolateRate);
    // The thread's scene names its converged configuration: the rate extrapolated.
    const auto thread = test::scene("tanpura-thread.json");
    CHECK(thread.simulation.extrapolateRate);
    CHECK(*thread.simulation.rateHz == 16e6);
    CHECK(*thread.simulation.modes == 2003);
}

TEST_CASE("every obstacle type and override parses")
{
    const auto s = parseScene(R"({"format": "jawari-scene/1",
        "string": {"damping": {"law": "constant", "sigma": 1.5}, "modes": [{"n": 2, "frequency": 400.5}]},
        "obstacles": [{"type": "profile", "x": [0.0, 0.004, 0.008], "height": [-1e-4, 0.0, -1e-4]},
                      {"type": "parabola", "position": 0.004, "width": 0.008, "curvature": 3.0, "height": 1e-5},
                      {"position": 0.3}],
        "pickup": {"quantity": "force"},
        "simulation": {"modes": 200, "rate": 480000, "duration": 0.5, "output_rate": 44100,
                       "residual_compliance": false, "residual_compliance_loss": 0.25, "static_pickup": false}})");
    CHECK_FALSE(s.simulation.residualCompliance);
    CHECK(s.simulation.residualComplianceLoss == 0.25);
    CHECK_FALSE(s.simulation.staticPickup);
    CHECK(s.string.damping.law == DampingLaw::constant);
    CHECK(s.string.damping.sigma == 1.5);
    const auto w = parseScene(R"({"format": "jawari-scene/1", "string": {"damping": {"law": "wavenumber",
        "sigma0": 0.6, "sigma1": 6.5e-3, "sigma3": 5e-6}}})");
    CHECK(w.string.damping.law == DampingLaw::wavenumber);
    CHECK(w.string.damping.sigma0 == 0.6);
    CHECK(w.string.damping.sigma1 == 6.5e-3);
    CHECK(w.string.damping.sigma3 == 5e-6);
    REQUIRE(s.string.modeOverrides.size() == 1);
    CHECK(*s.string.modeOverrides[0].frequencyHz == 400.5);
    REQUIRE(s.obstacles.size() == 3);
    CHECK(s.obstacles[0].type == ObstacleType::profile);
    CHECK(s.obstacles[0].heightAt(0.002) == Approx(-5e-5));
    CHECK(s.obstacles[1].type == ObstacleType::parabola);
    CHECK(s.obstacles[1].heightAt(0.004 + 0.002) == Approx(1e-5 - 0.5 * 3.0 * 0.002 * 0.002));
    CHECK(s.obstacles[2].type == ObstacleType::point);
    CHECK(s.pickup.quantity == PickupQuantity::force);
    CHECK(s.simulation.outputRateHz == 44100);
}

TEST_CASE("bad scenes are rejected with the field named")
{
    const std::vector<std::pair<std::string, std::string>> cases = {
        {R"({"format": "jawari-scene/1", )", "malformed JSON"},
        {R"([1, 2])", "(top level)"},
        {R"({"string": {}})", "format"},
        {R"({"format": "jawari-scene/2"})", "format"},
        {R"({"format": "jawari-scene/1", "strnig": {}})", "strnig: unknown field"},
        {R"({"format": "jawari-scene/1", "string": {"length": -1}})", "string.length: must be > 0"},
        {R"({"format": "jawari-scene/1", "string": {"length": 0}})", "string.length: must be > 0"},
        {R"({"format": "jawari-scene/1", "string": {"tension": "high"}})", "string.tension: must be a number"},
        {R"({"format": "jawari-scene/1", "string": {"linear_density": null}})",
         "string.linear_density: must be a number"},
        {R"({"format": "jawari-scene/1", "string": {"damping": {"law": "magic"}}})",
         "string.damping.law: unknown value"},
        {R"({"format": "jawari-scene/1", "string": {"damping": {"eta_air": -1}}})",
         "string.damping.eta_air: must be >= 0"},
        {R"({"format": "jawari-scene/1", "string": {"damping": {"sigma": 1}}})", "string.damping.sigma: is only used"},
        {R"({"format": "jawari-scene/1", "string": {"modes": [{"n": 0, "sigma": 1}]}})", "string.modes[0].n"},
        {R"({"format": "jawari-scene/1", "string": {"modes": [{"n": 1.5, "sigma": 1}]}})",
         "string.modes[0].n: must be a whole number"},
        {R"({"format": "jawari-scene/1", "string": {"modes": [{"n": 3}]}})",
         "string.modes[0]: needs a frequency or a sigma"},
        {R"({"format": "jawari-scene/1", "string": {"modes": [{"n": 2000, "sigma": 1}]}})",
         "string.modes[0].n: mode 2000 is above"},
        {R"({"format": "jawari-scene/1", "obstacles": {}})", "obstacles: must be an array"},
        {R"({"format": "jawari-scene/1", "obstacles": [{"type": "wall"}]})", "obstacles[0].type: unknown value"},
        {R"({"format": "jawari-scene/1", "obstacles": [{"position": 1.5}]})",
         "obstacles[0].position: must lie on the string"},
        {R"({"format": "jawari-scene/1", "obstacles": [{"position": 0}]})",
         "obstacles[0].position: must lie on the string"},
        {R"({"format": "jawari-scene/1", "obstacles": [{"stiffness": -3}]})", "obstacles[0].stiffness: must be > 0"},
        {R"({"format": "jawari-scene/1", "obstacles": [{"exponent": 0.5}]})",
         "obstacles[0].exponent: must be between 1 and 10"},
        {R"({"format": "jawari-scene/1", "obstacles": [{"width": 0}]})", "obstacles[0].width: must be > 0"},
        {R"({"format": "jawari-scene/1", "obstacles": [{"heigth": 0}]})", "obstacles[0].heigth: unknown field"},
        {R"({"format": "jawari-scene/1", "obstacles": [{}, {"type": "profile", "x": [0.1, 0.05], "height": [0, 0]}]})",
         "obstacles[1].x[1]: must be greater"},
        {R"({"format": "jawari-scene/1", "obstacles": [{"type": "profile", "x": [0.1, 0.2], "height": [0]}]})",
         "obstacles[0].height: must have as many entries"},
        {R"({"format": "jawari-scene/1", "obstacles": [{"type": "profile", "x": [0.1, 2.0], "height": [0, 0]}]})",
         "obstacles[0].x[1]: must lie on the string"},
        {R"({"format": "jawari-scene/1", "obstacles": [{"type": "profile", "height": [0, 0]}]})",
         "obstacles[0].x: is required"},
        {R"({"format": "jawari-scene/1", "obstacles": [{"type": "profile", "x": [0.1, 0.2], "height": [0, "a"]}]})",
         "obstacles[0].height[1]: must be a number"},
        {R"({"format": "jawari-scene/1", "obstacles": [{"type": "parabola", "position": 0.001, "width": 0.01}]})",
         "obstacles[0].width: the parabola"},
        {R"({"format": "jawari-scene/1", "excitation": {"type": "bow"}})", "excitation.type: unknown value"},
        {R"({"format": "jawari-scene/1", "excitation": {"position": -0.1}})",
         "excitation.position: must lie on the string"},
        {R"({"format": "jawari-scene/1", "excitation": {"amplitude": 1e999}})", "number overflow"},
        {R"({"format": "jawari-scene/1", "pickup": {"position": 1.002}})", "pickup.position: must lie on the string"},
        {R"({"format": "jawari-scene/1", "pickup": {"quantity": "loudness"}})", "pickup.quantity: unknown value"},
        {R"({"format": "jawari-scene/1", "simulation": {"method": "magic"}})", "simulation.method: unknown value"},
        {R"({"format": "jawari-scene/1", "simulation": {"rate": 0}})", "simulation.rate: must be > 0"},
        {R"({"format": "jawari-scene/1", "simulation": {"rate": 20000}})", "simulation.rate: the internal rate"},
        {R"({"format": "jawari-scene/1", "simulation": {"modes": 0}})", "simulation.modes: must be between 1"},
        {R"({"format": "jawari-scene/1", "simulation": {"contact_spacing": 0}})",
         "simulation.contact_spacing: must be > 0"},
        {R"({"format": "jawari-scene/1", "simulation": {"method": "realtime", "extrapolate_rate": true}})",
         "simulation.extrapolate_rate: applies to the reference only"},
        {R"({"format": "jawari-scene/1", "simulation": {"forcing": "static"}})", "simulation.forcing: "},
        {R"({"format": "jawari-scene/1", "simulation": {"contact_spacing": 0.6}})",
         "simulation.contact_spacing: must be between L/1e6 and L/2"},
        {R"({"format": "jawari-scene/1", "string": {"damping": {"law": "valette", "sigma3": 5e-6}}})",
         "string.damping.sigma3: is only used with law 'wavenumber'"},
        {R"({"format": "jawari-scene/1", "string": {"damping": {"law": "wavenumber", "sigma1": -1}}})",
         "string.damping.sigma1: must be >= 0"},
        {R"({"format": "jawari-scene/1", "simulation": {"static_pickup": 1}})",
         "simulation.static_pickup: must be true or false"},
        {R"({"format": "jawari-scene/1", "simulation": {"residual_compliance_loss": 1.5}})",
         "simulation.residual_compliance_loss: must be between 0 and 1"},
        {R"({"format": "jawari-scene/1", "simulation": {"modes": 10.5}})", "simulation.modes: must be a whole number"},
        {R"({"format": "jawari-scene/1", "simulation": {"duration": -1}})", "simulation.duration: must be > 0"},
        {R"({"format": "jawari-scene/1", "simulation": {"duration": 1e9}})",
         "simulation.duration: must be > 0 and at most"},
        {R"({"format": "jawari-scene/1", "simulation": {"output_rate": 100}})",
         "simulation.output_rate: must be between"},
        {R"({"format": "jawari-scene/1", "string": {"length": 0.3}})", "excitation.position: must lie on the string"},
    };
    for (const auto& [json, expected] : cases)
    {
        INFO("scene: " << json);
        std::string message;
        try
        {
            parseScene(json);
        }
        catch (const SceneError& e)
        {
            message = e.what();
        }
        INFO("error: " << message);
        CHECK_THAT(message, Catch::Matchers::Contains(expected));
    }
}
