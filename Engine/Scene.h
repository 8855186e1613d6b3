#pragma once
// jawari-scene/1 (DESIGN.md section 7): JSON, SI units, every field but `format` defaulted, every
// field checked. A bad scene throws SceneError naming the field by its path, e.g.
// "obstacles[1].stiffness: must be > 0 (got -3)". OFF.

#include "Obstacle.h"
#include "StringModel.h"

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

enum class PickupQuantity
{
    displacement,  // m
    velocity,      // m/s
    force          // N, on the termination at x = 0
};

enum class Method
{
    reference,    // the paper's configuration: M = N - 1 modes on the grid, resampled to the output
    realtime,     // the plugin's voice: truncated modes, R = oversampling x output rate, decimated
    quadratised,  // the voice with the non-iterative energy-quadratised contact
    penalty       // the voice with an explicit penalty force at u^n (unstable for stiff contact)
};

struct Excitation
{
    double position = 0.501;    // m
    double amplitude = 1.5e-3;  // m, triangular shape, zero velocity
};

struct Pickup
{
    double position = 0.992;  // m
    PickupQuantity quantity = PickupQuantity::displacement;
};

struct Simulation
{
    Method method = Method::reference;
    std::optional<double> rateHz;  // internal rate; reference default 2 MHz, realtime: automatic
    std::optional<int> modes;      // reference default 1001, realtime: automatic
    double durationSeconds = 1.0;
    int outputRateHz = 48000;
    bool residualCompliance = true;  // the voice's methods: the dropped modes' static compliance in series
};

struct Scene
{
    StringParameters string;
    std::vector<Obstacle> obstacles;
    Excitation excitation;
    Pickup pickup;
    Simulation simulation;
};

inline constexpr double kReferenceRateHz = 2'000'000.0;
inline constexpr int kReferenceModes = 1001;
inline constexpr int kMaxModes = 100000;
inline constexpr double kMaxDurationSeconds = 3600.0;

Scene parseScene(const std::string& jsonText);
Scene loadSceneFile(const std::string& path);

// Checks a scene's values after command-line overrides (the same rules as the parser).
void validateScene(const Scene& scene);

const char* methodName(Method m);
inline bool runsVoice(Method m)
{
    return m != Method::reference;
}
std::optional<Method> methodFromName(const std::string& name);
const char* quantityName(PickupQuantity q);
const char* quantityUnit(PickupQuantity q);

}  // namespace jawari
