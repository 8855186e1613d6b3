// A scene's "body" object (docs/scenes.md): read, its ranges checked, bad input named.

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
