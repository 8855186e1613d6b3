#pragma once
// Runs a scene offline: builds the solver its method asks for, plucks, steps at the internal rate,
// reads the pickup quantity, resamples to the output rate, and logs the energy. OFF.

#include "offline/DstTransform.h"
#include "offline/Scene.h"

#include <functional>
#include <memory>
#include <optional>
#include <vector>

namespace jawari
{

struct EnergySample
{
    double timeSeconds = 0.0;    // (n - 1/2) dt: H^{n-1/2} lives between steps
    double energy = 0.0;         // H, J
    double contactEnergy = 0.0;  // its contact part, J
    long newtonIterations = 0;   // summed over the internal steps since the previous sample
    int newtonMaxPerStep = 0;
};

struct RenderStats
{
    long long steps = 0;
    long long newtonIterationsTotal = 0;
    int newtonIterationsMax = 0;
    double maxPenetrationMetres = 0.0;
    int modes = 0;
    int activeModes = 0;  // modes actually stepped (ModalSolver::activeModeCount)
    double internalRateHz = 0.0;
    bool transformPath = false;
    double cpuSeconds = 0.0;
    // The reference's split steps over many modes (EngagedPoints): how many, the points they solved
    // (summed over them), points engaged afresh and steps solved again; all 0 when none split.
    long long splitSteps = 0, splitEngaged = 0, splitJoins = 0, splitResolves = 0;
    // At t = 0: the string's energy and the part of it stored in obstacles the initial shape
    // already presses into (large when a scene starts the string inside an obstacle).
    double initialEnergy = 0.0;
    double initialContactEnergy = 0.0;
};

struct RenderResult
{
    std::vector<double> output;  // pickup quantity at the output rate, SI units
    int outputRateHz = 48000;
    std::vector<EnergySample> energy;  // one per output sample when asked for
    RenderStats stats;
};

struct RenderOptions
{
    bool logEnergy = false;
    std::optional<ContactPath> path;  // force the reference's contact path (tests)
    // The "realtime" method with other strings on the body: each string meets the body through a
    // delayed link of this impedance (kg/s; SharedBody::setDelayedLink), a comparison. 0: the rigid bridge.
    double bodyLinkImpedance = 0.0;
    // Called now and then with the fraction done; return false to cancel (throws).
    std::function<bool(double)> progress;
};

RenderResult renderScene(const Scene& scene, const RenderOptions& options = {});

// The reference's solver for a scene, in its initial state (tests and tools that read the solver: the
// energy of each string on a body).
std::unique_ptr<ModalSolver> referenceSolver(const Scene& scene);

// The internal-rate signal and its solver, without resampling (tests compare solvers with it).
std::vector<double> renderInternal(const Scene& scene, long long steps, const RenderOptions& options = {},
                                   RenderStats* stats = nullptr);

}  // namespace jawari
