#include "offline/OfflineRender.h"

#include "offline/AutomaticQuality.h"
#include "offline/CpuClock.h"
#include "offline/DstTransform.h"
#include "offline/RealtimeRender.h"
#include "offline/Resampler.h"
#include "physics/body/ModalBody.h"
#include "physics/modes/ModalSolver.h"
#include "physics/string/StringDiscretisation.h"
#include "realtime/voice/Denormals.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <future>
#include <optional>
#include <stdexcept>
#include <string>

namespace jawari
{
namespace
{

// What the "bridge_force" quantity reads: the points on the body (every obstacle's without one).
struct BridgeReading
{
    std::vector<int> points;

    double force(const ModalSolver& solver) const  // N on the bridge, the step's
    {
        double sum = 0.0;
        for (const int j : points)
            sum -= solver.contactForce(j);
        return sum;
    }
};

struct SolverSetup
{
    ModalSolverConfig config;
    std::vector<double> initial;
    double rateHz = 0.0;
    BridgeReading bridge;
};

}  // namespace

namespace
{
// Which of the configuration's contact points stand on the body (every obstacle's without a body):
// those of the body's obstacles (each obstacle's points follow the previous one's, contactPointsOnGrid's
// order); the polarisations' coupling points after them do not.
std::vector<char> pointsOnBody(const std::vector<Obstacle>& obstacles, const std::optional<SceneBody>& body, double L,
                               int gridIntervals, size_t pointCount)
{
    auto on = contactPointsOnBody(obstacles, obstaclesOnBody(obstacles.size(), body), L, gridIntervals);
    on.resize(pointCount, 0);
    return on;
}

// Another string on the body, its modes after those before it (appendString), plucked from its own
// shape; every contact point of it stands on the body.
void addString(SolverSetup& s, const Scene& scene, const BodyString& other, std::vector<char>& onBody)
{
    const int M = scene.simulation.modes.value_or(kReferenceModes);
    auto config = stringSolverConfig(other.string, other.obstacles, M, s.rateHz, 0.5 * other.string.lengthMetres,
                                     PickupQuantity::displacement);
    config.pickupWeights.clear();
    appendString(s.config, config);
    const double scale = std::sqrt(other.string.linearDensity / scene.string.linearDensity);  // q' = scale q
    for (const double q : pluckModalShape(other.string.lengthMetres, M, other.excitation.position,
                                          other.excitation.amplitude))
        s.initial.push_back(scale * q);
    onBody.resize(onBody.size() + config.contacts.size(), 1);
}

// The body's modes after the strings' (ModalBody.h), at rest; the pressure pickup reads them.
void addBody(SolverSetup& s, const Scene& scene, const std::vector<char>& onBody)
{
    const auto& body = *scene.body;
    const int stringModes = s.config.modes.size();
    s.config = withBody(s.config, {&body.body, onBody, body.coupling});
    s.initial.resize(size_t(s.config.modes.size()), 0.0);
    if (scene.pickup.quantity == PickupQuantity::pressure)
        s.config.pickupWeights =
            radiationWeights(body.body, stringModes, scene.string.linearDensity, pickupListener(scene));
}

// The reference (docs/design.md section 2): M = N - 1 modes, distributed obstacles sampled on their
// own contact grid (Obstacle.h: their spacing, else the scene's contact spacing, else L/1002), point
// obstacles at their own positions.
SolverSetup referenceSetup(const Scene& scene, std::optional<ContactPath> path)
{
    SolverSetup s;
    const int M = scene.simulation.modes.value_or(kReferenceModes);
    s.rateHz = scene.simulation.rateHz.value_or(kReferenceRateHz);
    auto obstacles = scene.obstacles;
    if (const auto spacing = scene.simulation.contactSpacingMetres)
        for (auto& o : obstacles)
            if (o.isDistributed() && o.spacing == 0.0)
                o.spacing = *spacing;
    s.config = stringSolverConfig(scene.string, obstacles, M, s.rateHz, scene.pickup.position, scene.pickup.quantity);
    s.config.staticExactForcing = scene.simulation.staticExactForcing;
    s.initial = pluckModalShape(scene.string.lengthMetres, M, scene.excitation.position, scene.excitation.amplitude);
    if (const auto& force = scene.excitation.force)
    {
        s.config.excitationPosition = force->position;
        s.config.excitationShape = forcePluckModalShape(scene.string.lengthMetres, M, *force);
    }
    if (const auto& second = scene.secondPolarisation)
    {
        // Both polarisations: the pluck along its angle, cos to the vertical and sin to the other.
        s.config = twoPolarisationConfig(s.config, *second);
        const double angle = scene.excitation.angle;
        s.initial.resize(2 * size_t(M), 0.0);
        for (int p = 0; p < M; ++p)
        {
            s.initial[size_t(M + p)] = std::sin(angle) * s.initial[size_t(p)];
            s.initial[size_t(p)] *= std::cos(angle);
        }
    }
    else if (!scene.body)
        chooseContactPath(s.config, path.value_or(scene.simulation.staticExactForcing ? ContactPath::projection
                                                                                      : ContactPath::automatic));
    auto onBody = pointsOnBody(obstacles, scene.body, scene.string.lengthMetres, M + 1, s.config.contacts.size());
    if (scene.body)
    {
        if (path == ContactPath::transform)
            throw std::invalid_argument("a body couples the contact points: it takes the projection path");
        for (const auto& other : scene.body->strings)
            addString(s, scene, other, onBody);
        addBody(s, scene, onBody);
    }
    for (size_t j = 0; j < onBody.size(); ++j)
        if (onBody[j])
            s.bridge.points.push_back(int(j));
    return s;
}

// Steps the solver, handing each internal sample of the pickup quantity to `sink`, and each
// step's solver to `afterStep` (energy log). Velocity is the centred difference (u^{n+1} - u^{n-1})/2dt,
// and pressure the same of the body's radiation reading; the bridge force is the step's contact
// forces at the bridge's points, negated.
// A force pluck pushes at each step's start.
template <typename Sink, typename AfterStep>
void run(ModalSolver& solver, const Scene& scene, const BridgeReading& bridge, long long steps,
         RenderStats& stats, const RenderOptions& options, Sink&& sink, AfterStep&& afterStep)
{
    const PickupQuantity quantity = scene.pickup.quantity;
    const auto& force = scene.excitation.force;
    ScopedFlushDenormals noDenormals;
    const double dt = solver.timeStep();
    // The pluck starts from rest, so the velocity at n = 0 is 0 exactly.
    double yPrev = 0.0;
    double y = solver.pickup();
    const double start = threadCpuSeconds();
    const long long progressEvery = 1 << 16;
    for (long long n = 0; n < steps; ++n)
    {
        if (force)  // explicit in the step from t^n (ModalSolver::setExternalForce)
            solver.setExternalForce(forcePluckNewtons(*force, double(n) * dt));
        solver.step();
        const double yNext = solver.pickup();
        double sample = y;
        if (quantity == PickupQuantity::velocity || quantity == PickupQuantity::pressure)
            sample = n == 0 ? 0.0 : (yNext - yPrev) / (2.0 * dt);
        else if (quantity == PickupQuantity::bridgeForce)  // the step's contact force, centred on t^n
            sample = bridge.force(solver);
        sink(sample);
        yPrev = y;
        y = yNext;
        const int it = solver.lastIterations();
        stats.newtonIterationsTotal += it;
        stats.newtonIterationsMax = std::max(stats.newtonIterationsMax, it);
        if (solver.contactCount() > 0)
            stats.maxPenetrationMetres = std::max(stats.maxPenetrationMetres, solver.lastMaxPenetration());
        afterStep(n, it);
        if (options.progress && (n % progressEvery) == 0 && !options.progress(double(n) / double(steps)))
            throw std::runtime_error("render cancelled");
    }
    stats.cpuSeconds += threadCpuSeconds() - start;
    stats.steps += steps;
    const auto& split = solver.splitCounters();
    stats.splitSteps = split.steps;
    stats.splitEngaged = split.engaged;
    stats.splitJoins = split.joins;
    stats.splitResolves = split.resolves;
    if (options.progress)
        options.progress(1.0);
}

}  // namespace

void describeSolver(ModalSolver& solver, double rateHz, RenderStats& stats)
{
    stats.modes = solver.modeCount();
    stats.activeModes = solver.activeModeCount();
    stats.internalRateHz = rateHz;
    stats.transformPath = solver.usesTransform();
    const auto H = solver.energy();
    stats.initialEnergy = H.total;
    stats.initialContactEnergy = H.contact;
}

std::unique_ptr<ModalSolver> referenceSolver(const Scene& scene)
{
    validateScene(scene);
    const auto setup = referenceSetup(scene, std::nullopt);
    auto solver = std::make_unique<ModalSolver>(setup.config);
    solver->setInitialDisplacement(setup.initial);
    return solver;
}

std::vector<double> renderInternal(const Scene& scene, long long steps, const RenderOptions& options,
                                   RenderStats* statsOut)
{
    validateScene(scene);
    if (scene.simulation.extrapolateRate)
        throw std::invalid_argument("a reference with its rate extrapolated has no one internal-rate signal");
    auto setup = referenceSetup(scene, options.path);
    ModalSolver solver(setup.config);
    solver.setInitialDisplacement(setup.initial);
    RenderStats stats;
    describeSolver(solver, setup.rateHz, stats);
    std::vector<double> out;
    out.reserve(static_cast<size_t>(steps));
    run(
        solver, scene, setup.bridge, steps, stats, options, [&](double v) { out.push_back(v); },
        [](long long, int) {});
    if (statsOut)
        *statsOut = stats;
    return out;
}

namespace
{
// The reference's pickup samples resampled to the output rate. The string was held in its initial
// shape before t = 0: the resampler sees the signal minus its first sample (so no step at t = 0, as
// if the held value had always been there), and that sample is added back to the output (the filter
// passes a constant unchanged).
class HeldStartResampler
{
public:
    HeldStartResampler(double inputRateHz, double outputRateHz, std::vector<double>& output)
        : resampler_(inputRateHz, outputRateHz)
        , output_(output)
    {
        chunk_.reserve(kChunk);
    }

    void push(double v)
    {
        if (!held_)
            held_ = v;
        chunk_.push_back(v - *held_);
        if (chunk_.size() == kChunk)
        {
            resampler_.push(chunk_.data(), chunk_.size(), output_);
            chunk_.clear();
        }
    }

    void finish()
    {
        resampler_.push(chunk_.data(), chunk_.size(), output_);
        resampler_.finish(output_);
        for (double& v : output_)
            v += held_.value_or(0.0);
    }

private:
    static constexpr size_t kChunk = 4096;
    Resampler resampler_;
    std::vector<double>& output_;
    std::vector<double> chunk_;
    std::optional<double> held_;
};

// The energy log: H^{n+1/2} after the step that produced internal sample n = round(m rate / outRate),
// one row per output sample m, with the Newton iterations since the previous row.
class EnergyLog
{
public:
    EnergyLog(ModalSolver& solver, double rateHz, int outputRateHz, size_t rows, std::vector<EnergySample>& log)
        : solver_(solver)
        , rateHz_(rateHz)
        , outputRateHz_(outputRateHz)
        , rows_(rows)
        , log_(log)
    {
        log_.reserve(rows);
    }

    void afterStep(long long n, int iterations)
    {
        iterationsSince_ += iterations;
        iterationsMaxSince_ = std::max(iterationsMaxSince_, iterations);
        if (static_cast<size_t>(nextLogged_) >= rows_)
            return;
        const long long target = std::llround(double(nextLogged_) * rateHz_ / outputRateHz_);
        if (n < target)
            return;
        const auto H = solver_.energy();
        log_.push_back({(double(n) + 0.5) / rateHz_, H.total, H.contact, iterationsSince_, iterationsMaxSince_});
        iterationsSince_ = 0;
        iterationsMaxSince_ = 0;
        ++nextLogged_;
    }

private:
    ModalSolver& solver_;
    double rateHz_;
    int outputRateHz_;
    size_t rows_;
    std::vector<EnergySample>& log_;
    long nextLogged_ = 0;
    long iterationsSince_ = 0;
    int iterationsMaxSince_ = 0;
};
}  // namespace

namespace
{
RenderResult renderReference(const Scene& scene, const RenderOptions& options)
{
    auto setup = referenceSetup(scene, options.path);
    ModalSolver solver(setup.config);
    solver.setInitialDisplacement(setup.initial);

    RenderResult result;
    result.outputRateHz = scene.simulation.outputRateHz;
    describeSolver(solver, setup.rateHz, result.stats);
    const double duration = scene.simulation.durationSeconds;
    const long long steps = std::llround(duration * setup.rateHz);
    const size_t outputCount = static_cast<size_t>(std::llround(duration * result.outputRateHz));
    result.output.reserve(outputCount + 16);

    HeldStartResampler output(setup.rateHz, result.outputRateHz, result.output);
    std::optional<EnergyLog> log;
    if (options.logEnergy)
        log.emplace(solver, setup.rateHz, result.outputRateHz, outputCount, result.energy);
    run(
        solver, scene, setup.bridge, steps, result.stats, options, [&](double v) { output.push(v); },
        [&](long long n, int iterations) {
            if (log)
                log->afterStep(n, iterations);
        });
    output.finish();
    result.output.resize(outputCount, 0.0);
    for (double v : result.output)
        if (!std::isfinite(v))
            throw std::runtime_error("the simulation produced a non-finite sample");
    return result;
}

// The reference at its rate R and at 2R, combined as 2 y(2R) - y(R) (Simulation::extrapolateRate): an
// error c / R in each cancels. The two renders share nothing but the FFTW planner, which is locked:
// the coarse one runs on a thread of its own beside the fine one, and either's failure stops the
// other. The energy log, the rate and the modes are the finer render's; the steps, Newton iterations
// and CPU time both renders', the largest iterations and penetration either's.
RenderResult renderExtrapolated(const Scene& scene, const RenderOptions& options)
{
    Scene coarse = scene;
    coarse.simulation.extrapolateRate = false;
    Scene fine = coarse;
    fine.simulation.rateHz = 2.0 * coarse.simulation.rateHz.value_or(kReferenceRateHz);
    std::atomic<double> coarseDone{0.0};
    std::atomic<bool> stop{false};
    RenderOptions first = options, second = options;
    first.logEnergy = false;
    first.progress = [&](double done) {
        coarseDone = done;
        return !stop;
    };
    // The finer render takes twice the steps: the fraction done is a third of the one and two of the other.
    second.progress = [&](double done) {
        return !stop && (!options.progress || options.progress((coarseDone + 2.0 * done) / 3.0));
    };
    auto coarseRender = std::async(std::launch::async, [&] {
        try
        {
            return renderReference(coarse, first);
        }
        catch (...)
        {
            stop = true;
            throw;
        }
    });
    RenderResult result;
    try
    {
        result = renderReference(fine, second);
    }
    catch (...)
    {
        const bool coarseFailedFirst = stop.exchange(true);  // else this failure stops it
        try
        {
            coarseRender.get();
        }
        catch (...)
        {
            if (coarseFailedFirst)
                throw;  // its error stopped this render: the one to report
        }
        throw;
    }
    const RenderResult low = coarseRender.get();
    if (options.progress)
        options.progress(1.0);  // both done (the fine render's last report waited for neither)
    for (size_t i = 0; i < result.output.size(); ++i)
        result.output[i] = 2.0 * result.output[i] - low.output[i];
    auto& stats = result.stats;
    stats.cpuSeconds += low.stats.cpuSeconds;
    stats.steps += low.stats.steps;
    stats.newtonIterationsTotal += low.stats.newtonIterationsTotal;
    stats.newtonIterationsMax = std::max(stats.newtonIterationsMax, low.stats.newtonIterationsMax);
    stats.maxPenetrationMetres = std::max(stats.maxPenetrationMetres, low.stats.maxPenetrationMetres);
    stats.splitSteps += low.stats.splitSteps;
    stats.splitEngaged += low.stats.splitEngaged;
    stats.splitJoins += low.stats.splitJoins;
    stats.splitResolves += low.stats.splitResolves;
    return result;
}
}  // namespace

RenderResult renderScene(const Scene& scene, const RenderOptions& options)
{
    validateScene(scene);
    if (!scene.simulation.reference)
        return renderRealtime(scene, options);
    return scene.simulation.extrapolateRate ? renderExtrapolated(scene, options) : renderReference(scene, options);
}

}  // namespace jawari
