#pragma once
// jawari-scene/1 (docs/scenes.md): JSON, SI units, every field but `format` defaulted, every
// field checked. A bad scene throws SceneError naming the field by its path, e.g.
// "obstacles[1].stiffness: must be > 0 (got -3)". OFF.

#include "physics/contact/ContactMethod.h"
#include "physics/string/ForcePluck.h"
#include "physics/body/ModalBody.h"
#include "physics/contact/Obstacle.h"
#include "physics/modes/Pickup.h"
#include "physics/string/Polarisations.h"
#include "physics/string/StringModel.h"

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace jawari
{

class SceneError : public std::runtime_error
{
public:
    SceneError(std::string path, const std::string& message)
        : std::runtime_error(path.empty() ? message : path + ": " + message)
        , path_(std::move(path))
    {}
    const std::string& path() const { return path_; }

private:
    std::string path_;
};

struct Excitation
{
    double position = 0.501;    // m
    double amplitude = 1.5e-3;  // m, triangular shape, zero velocity
    double angle = 0.0;         // rad from the vertical (two polarisations: cos to the vertical, sin to the other)
    // Instead of the triangle: the string from rest, pushed by DAFx-16's force pluck (its position
    // the excitation's). The reference only, one polarisation.
    std::optional<ForcePluck> force;
};

struct Pickup
{
    double position = 0.992;  // m
    PickupQuantity quantity = PickupQuantity::displacement;
    std::string listener;  // "pressure": the body's listener by name (empty: its first)
};

struct Simulation
{
    // The reference (the paper's configuration: M = N - 1 modes on the grid, resampled to the
    // output), or the plugin's voice (truncated modes, R = oversampling x output rate, decimated)
    // with its contact solved by `contact`. A scene's "method" names one of the two: "reference",
    // or a contact method's scene name (kContactMethods).
    bool reference = true;
    ContactMethod contact = ContactMethod::energyConserving;
    std::optional<double> rateHz;  // internal rate; reference default 2 MHz, realtime: automatic
    std::optional<int> modes;      // reference default 1001, realtime: automatic
    // The reference's contact points on every distributed obstacle that gives no spacing of its own
    // (m); empty: the contact grid's, L/1002 (Obstacle.h). The voice keeps its own points.
    std::optional<double> contactSpacingMetres;
    // The reference only: rendered at the rate and at twice it, the output 2 y(2R) - y(R) (Richardson's
    // extrapolation of an error first order in the step: a contact shorter than a step).
    bool extrapolateRate = false;
    // Each mode answers a force by its static compliance where the paper's gain dt^2/mu is too much
    // (ModalSolverConfig::staticExactForcing), in the reference or the voice. A scene's "forcing":
    // "paper" (the default) or "static-exact".
    bool staticExactForcing = false;
    double durationSeconds = 1.0;
    int outputRateHz = 48000;
    bool residualCompliance = true;  // the voice's methods: the dropped modes' static compliance in series
    // Its loss share theta in [0, 1] (VoiceConfig::residualComplianceLoss); empty: the voice's rule.
    std::optional<double> residualComplianceLoss;
    bool staticPickup = true;  // the voice's methods: the modes above the output's Nyquist frequency read statically

    // Drops the modes, rate and contact spacing chosen for one solver: the reference's defaults (the
    // paper's configuration) or the voice's automatic choice apply.
    void forgetConfiguration()
    {
        modes.reset();
        rateHz.reset();
        contactSpacingMetres.reset();
        extrapolateRate = false;
        staticExactForcing = false;
    }
};

// Another string on the body, every obstacle of it standing there: the drone's other strings.
struct BodyString
{
    StringParameters string;
    std::vector<Obstacle> obstacles;
    Excitation excitation;  // amplitude 0: at rest
};

// The instrument's body under the bridge (ModalBody.h): a factory body or listed modes, and the
// obstacles that stand on it, and the other strings on it (the reference only).
struct SceneBody
{
    ModalBody body;
    std::vector<int> obstacles;  // indices into Scene::obstacles
    double coupling = 1.0;       // scales the body's coupling rows; 0: the body never moves
    std::vector<BodyString> strings;
};

// One flag per obstacle: whether it stands on the body (every obstacle without a body).
std::vector<char> obstaclesOnBody(size_t obstacleCount, const std::optional<SceneBody>& body);

struct Scene;
// The index of the body's listener that the scene's "pressure" pickup hears (0 without a name; -1
// for a name the body lacks, which validation refuses).
int pickupListener(const Scene& scene);

struct Scene
{
    StringParameters string;
    std::vector<Obstacle> obstacles;
    Excitation excitation;
    Pickup pickup;
    Simulation simulation;
    // The string's second transverse polarisation (Polarisations.h), or one polarisation. Its
    // excitationAngle is the excitation's angle.
    std::optional<SecondPolarisation> secondPolarisation;
    std::optional<SceneBody> body;
};

inline constexpr double kMaxDurationSeconds = 3600.0;

Scene parseScene(const std::string& jsonText);
Scene loadSceneFile(const std::string& path);

// Checks a scene's values after command-line overrides (the same rules as the parser).
void validateScene(const Scene& scene);

// "reference" or the voice's contact method's scene name.
const char* methodName(const Simulation& simulation);
// Sets reference/contact from a method's name; false (nothing changed) for an unknown name.
bool setMethodByName(Simulation& simulation, const std::string& name);
const char* quantityName(PickupQuantity q);
const char* quantityUnit(PickupQuantity q);

}  // namespace jawari
