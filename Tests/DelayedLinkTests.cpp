// The delayed link between strings and body (SharedBody::setDelayedLink), a comparison: each string
// meets the body through a lossless line whose waves take one step. Its energy balance holds with
// the waves in transit counted, and it differs from the rigid bridge at first order in the step.

#include "SharedBodySupport.h"
#include "TestSupport.h"

#include "offline/Analysis.h"
#include "offline/OfflineRender.h"
#include "offline/Scene.h"
#include "physics/body/FactoryBodies.h"
#include "physics/body/SharedBody.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <vector>

using namespace jawari;

namespace
{
using test::scene;

// tanpura-sa with tanpura-pa beside it on the tanpura body, the body's radiated sound the output,
// by the voice at `rateHz` (its automatic modes: 253 at every rate here).
Scene droneOnBody(double rateHz, double seconds)
{
    Scene drone = scene("tanpura-sa.json");
    const Scene pa = scene("tanpura-pa.json");
    drone.body = SceneBody{*factoryBody("tanpura"), {0}, 1.0, {}};
    drone.body->strings.push_back({pa.string, pa.obstacles, pa.excitation});
    drone.body->strings.back().excitation.position = 0.45;
    drone.pickup.quantity = PickupQuantity::pressure;
    drone.simulation.reference = false;
    drone.simulation.forgetConfiguration();
    drone.simulation.rateHz = rateHz;
    drone.simulation.modes = 253;
    drone.simulation.durationSeconds = seconds;
    return drone;
}
}  // namespace

TEST_CASE("A delayed link keeps the joined energy with its waves in transit: 1e-9 lossless over 1e5 steps",
          "[body][energy]")
{
    // tanpura-sa and tanpura-pa plucked, lossless, each on its own line of 20 kg/s to the lossless
    // tanpura body, 150 modes at 192 kHz.
    const ModalBody body = test::tanpuraBody(true);
    auto strings = test::stringsOf({scene("tanpura-sa.json"), scene("tanpura-pa.json")}, {true, true}, true, true);
    SharedBody shared(body, 1.0, 1.0 / test::kBodyTestRate);
    shared.setDelayedLink(20.0);
    const double H0 = shared.energy(strings.pointers.data(), 2);
    double drift = 0.0, inTransit = 0.0, bridge = 0.0;
    long pressing = 0;
    for (long n = 0; n < 100000; ++n)
    {
        shared.step(strings.pointers.data(), 2);
        drift = std::max(drift, std::abs(shared.energy(strings.pointers.data(), 2) / H0 - 1.0));
        inTransit = std::max(inTransit, shared.lineEnergy(2) / H0);
        bridge = std::max(bridge, std::abs(shared.bridgeDisplacement()));
        pressing += shared.lastBridgeForce() != 0.0;
    }
    INFO("relative drift " << drift << ", the lines held up to " << inTransit
                           << " of the energy, the bridge moved up to " << bridge << " m, " << pressing
                           << " steps pressing");
    CHECK(pressing > 1000);
    CHECK(bridge > 1e-7);
    CHECK(inTransit > 1e-7);  // without the waves in transit the balance would miss this much
    CHECK(drift < 1e-9);
    CHECK_THROWS_WITH(shared.setDelayedLink(-1.0), Catch::Contains("impedance"));
}

TEST_CASE("A delayed link moves the body's sound from the rigid bridge's at first order in the step", "[body]")
{
    // The radiated sound of tanpura-sa and tanpura-pa on the tanpura body over 0.2 s, each string on a
    // line of 5 or 20 kg/s, against the rigid bridge at the same rate: the difference halves with the
    // step, and at the instrument's 288 kHz it is what the delay costs.
    // The floor: the rigid bridge against itself with both plucks raised by 1e-4.
    const Scene base = droneOnBody(288000.0, 0.2);
    Scene raised = base;
    raised.excitation.amplitude *= 1.0001;
    raised.body->strings[0].excitation.amplitude *= 1.0001;
    const auto rigidBase = renderScene(base).output;
    const double floor = relativeL2(renderScene(raised).output, rigidBase, rigidBase.size());
    std::vector<double> previous;
    for (const double impedance : {5.0, 20.0})
    {
        previous.clear();
        for (const double rate : {288000.0, 576000.0, 1152000.0})
        {
            const Scene scene = droneOnBody(rate, 0.2);
            const auto rigid = renderScene(scene).output;
            RenderOptions linked;
            linked.bodyLinkImpedance = impedance;
            const auto link = renderScene(scene, linked).output;
            const double relL2 = relativeL2(link, rigid, rigid.size());
            const double lsd = logSpectralDistance(link, rigid, scene.simulation.outputRateHz, 0.2);
            INFO(impedance << " kg/s at " << rate << " Hz: relL2 " << relL2 << ", LSD " << lsd << " dB; the floor "
                           << floor);
            if (rate == 288000.0)
                CHECK(relL2 > 100.0 * floor);  // far beyond what a change of 1e-4 in the plucks moves
            if (!previous.empty())
            {
                INFO("the rate doubled from " << rate / 2 << " Hz: " << previous.back() / relL2 << " times closer");
                CHECK(previous.back() / relL2 > 1.6);
                CHECK(previous.back() / relL2 < 2.6);
            }
            previous.push_back(relL2);
        }
    }
}
