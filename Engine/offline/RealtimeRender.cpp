#include "offline/RealtimeRender.h"

#include "offline/AutomaticQuality.h"
#include "offline/CpuClock.h"
#include "physics/body/SharedBody.h"
#include "realtime/voice/Decimator.h"
#include "realtime/voice/Denormals.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>

namespace jawari
{

VoiceConfig voiceConfigFor(const Scene& scene)
{
    const auto q = automaticQuality(scene);
    VoiceConfig v;
    v.string = scene.string;
    // Only what the string can reach (AutomaticQuality.h, reachAt): an obstacle beyond it never touches.
    const auto onBody = obstaclesOnBody(scene.obstacles.size(), scene.body);
    for (size_t i = 0; i < scene.obstacles.size(); ++i)
        if (obstacleReachable(scene, scene.obstacles[i]))
        {
            v.obstacles.push_back(scene.obstacles[i]);
            v.obstacleOnBody.push_back(onBody[i]);
        }
    if (scene.body)
    {
        v.body = scene.body->body;
        v.bodyCoupling = scene.body->coupling;
        v.listener = pickupListener(scene);
    }
    v.excitationPosition = scene.excitation.position;
    v.pickupPosition = scene.pickup.position;
    v.quantity = scene.pickup.quantity;
    v.modes = q.modes;
    v.oversampling = q.oversampling;
    v.hostRateHz = scene.simulation.outputRateHz;
    v.residualCompliance = scene.simulation.residualCompliance;
    v.residualComplianceLoss = scene.simulation.residualComplianceLoss;
    v.staticExactForcing = scene.simulation.staticExactForcing;
    v.staticPickupAboveNyquist = scene.simulation.staticPickup;
    if (scene.simulation.contact == ContactMethod::energyConserving)
        v.reach = [scene](double x) { return reachAt(scene, x); };
    v.method = scene.simulation.contact;
    v.secondPolarisation = scene.secondPolarisation;
    return v;
}

namespace
{
// Why a voice render stopped: the explicit methods lose stability at stiff contact (a higher rate
// or the default method helps); the default never gains energy, so its guard tripping is a fault.
std::string lostStabilityMessage(const Simulation& simulation, long restarts)
{
    const std::string what = std::string("the ") + methodName(simulation)
                             + " method's output ran beyond what its energy allows (" + std::to_string(restarts)
                             + " restarts from rest)";
    if (simulation.contact == ContactMethod::energyConserving)
        return what + "; this method never gains energy, so this is a fault in Jawari: please report the scene";
    return what + ": it lost stability; try a higher rate, or the default method ("
           + contactMethodName(ContactMethod::energyConserving).sceneName + ")";
}

// The voice, plucked from the scene's triangular shape at rest like the reference.
RenderResult renderVoice(const Scene& scene, const RenderOptions& options)
{
    Voice voice(voiceConfigFor(scene));
    voice.setInitialShape(scene.excitation.position, scene.excitation.amplitude);
    RenderResult result;
    result.outputRateHz = scene.simulation.outputRateHz;
    auto& stats = result.stats;
    describeSolver(voice.solver(), voice.internalRateHz(), stats);
    const size_t count = static_cast<size_t>(std::llround(scene.simulation.durationSeconds * result.outputRateHz));
    const size_t latency = static_cast<size_t>(voice.latencySamples());
    std::vector<double> raw(count + latency);
    const size_t block = 256;
    ScopedFlushDenormals noDenormals;
    const double start = threadCpuSeconds();
    for (size_t m = 0; m < raw.size(); m += block)
    {
        const size_t n = std::min(block, raw.size() - m);
        for (size_t i = 0; i < n; ++i)
        {
            voice.process(raw.data() + m + i, 1);
            const long iterations = voice.takeIterationCount();
            const int most = voice.takeMaxIterations();
            stats.newtonIterationsTotal += iterations;
            stats.newtonIterationsMax = std::max(stats.newtonIterationsMax, most);
            if (options.logEnergy && m + i < count)
            {
                const auto H = voice.solver().energy();
                result.energy.push_back(
                    {double(m + i + 1) / result.outputRateHz, H.total, H.contact, iterations, most});
            }
        }
        stats.maxPenetrationMetres = std::max(stats.maxPenetrationMetres, voice.takeMaxPenetration());
        if (options.progress && !options.progress(double(m) / double(raw.size())))
            throw std::runtime_error("render cancelled");
    }
    stats.cpuSeconds = threadCpuSeconds() - start;
    stats.steps = static_cast<long long>(raw.size()) * voice.oversampling();
    if (voice.blowUps() > 0)
        throw std::runtime_error(lostStabilityMessage(scene.simulation, voice.blowUps()));
    result.output.assign(raw.begin() + static_cast<std::ptrdiff_t>(latency), raw.end());
    return result;
}


// Another string on the body (a sympathetic string) as a voice: the modes its automatic quality
// asks for, at the played voice's internal rate, every obstacle kept (the body, not its pluck,
// may drive it), on the moving bridge.
VoiceConfig otherStringConfig(const Scene& scene, const BodyString& other, const VoiceConfig& played)
{
    Scene alone = scene;
    alone.string = other.string;
    alone.obstacles = other.obstacles;
    alone.excitation = other.excitation;
    alone.body.reset();
    alone.secondPolarisation.reset();
    VoiceConfig v;
    v.string = other.string;
    v.obstacles = other.obstacles;
    v.excitationPosition = v.pickupPosition = other.excitation.position;
    v.quantity = PickupQuantity::displacement;
    v.modes = automaticQuality(alone).modes;
    v.oversampling = played.oversampling;
    v.hostRateHz = played.hostRateHz;
    v.residualCompliance = played.residualCompliance;
    v.residualComplianceLoss = played.residualComplianceLoss;
    v.staticExactForcing = played.staticExactForcing;
    v.method = ContactMethod::energyConserving;
    v.ownDecimator = false;
    v.movingBridge = true;
    return v;
}

// The scene's string and the body's other strings, each a voice on one SharedBody (the played
// string first, the others after it: linear when every point of theirs is a spring).
struct VoicesOnBody
{
    std::vector<std::unique_ptr<Voice>> voices;
    std::vector<ModalSolver*> solvers;
    std::vector<char> plucked;  // per voice: plucked from a shape (the others start at rest)
    std::unique_ptr<SharedBody> body;
    int split = 0;

    // One host sample's internal steps of every voice and the body, as the instrument steps them
    // (Instrument::stepBodyOnce): into `internal`, the played string's pickup, or the body's
    // radiated pressure at its listener when `pressure`.
    void stepHostSample(double* internal, bool pressure)
    {
        // A string never plucked can hold no more than the plucked ones have had between them (the
        // instrument's ceiling for its sympathetic strings).
        double supply = 0.0;
        for (size_t i = 0; i < voices.size(); ++i)
            supply += plucked[i] ? voices[i]->energyCeiling() : 0.0;
        for (size_t i = 0; i < voices.size(); ++i)
            if (!plucked[i])
                voices[i]->allowEnergy(supply);
        // Banked strings (SharedBody::bankLinear) are stepped by the body, their voices left alone.
        const size_t own = body->banked() ? size_t(split) : voices.size();
        for (int k = 0; k < voices[0]->oversampling(); ++k)
        {
            for (size_t i = 0; i < own; ++i)
                voices[i]->beginOnBody();
            body->step(solvers.data(), static_cast<int>(solvers.size()), split);
            internal[k] = voices[0]->finishOnBody();
            for (size_t i = 1; i < own; ++i)
                voices[i]->finishOnBody();
            if (pressure)
                internal[k] = body->pressure(0);
        }
    }
};

VoicesOnBody voicesOnBody(const Scene& scene)
{
    const auto& sceneBody = *scene.body;
    VoiceConfig played = voiceConfigFor(scene);
    played.body.reset();
    played.obstacleOnBody.clear();
    played.movingBridge = true;
    played.ownDecimator = false;
    if (played.quantity == PickupQuantity::pressure)
        played.quantity = PickupQuantity::velocity;  // unheard: the body's sound is the output
    const bool othersPlucked = std::any_of(sceneBody.strings.begin(), sceneBody.strings.end(),
                                           [](const BodyString& s) { return s.excitation.amplitude != 0.0; });
    if (othersPlucked)
        played.reach = nullptr;  // its pluck's energy no longer bounds its motion
    VoicesOnBody v;
    v.voices.push_back(std::make_unique<Voice>(played));
    v.voices[0]->setInitialShape(scene.excitation.position, scene.excitation.amplitude);
    v.plucked.push_back(1);
    for (const auto& other : sceneBody.strings)
    {
        v.voices.push_back(std::make_unique<Voice>(otherStringConfig(scene, other, played)));
        v.plucked.push_back(other.excitation.amplitude != 0.0);
        if (v.plucked.back())
            v.voices.back()->setInitialShape(other.excitation.position, other.excitation.amplitude);
    }
    v.body = std::make_unique<SharedBody>(sceneBody.body, sceneBody.coupling, v.voices[0]->solver().timeStep());
    const bool othersLinear = std::all_of(v.voices.begin() + 1, v.voices.end(), [](const auto& voice) {
        return SharedBody::standsOnSprings(voice->solver());
    });
    v.split = othersLinear ? 1 : static_cast<int>(v.voices.size());
    v.body->listenAt(pickupListener(scene));
    for (size_t i = 0; i < v.voices.size(); ++i)
    {
        auto& solver = v.voices[i]->solver();
        if (int(i) < v.split)
            v.body->check(solver);
        else
            v.body->checkLinear(solver);
        v.solvers.push_back(&solver);
    }
    return v;
}

// The scene's string and the body's other strings in lockstep with the body, one internal step at a
// time, as the instrument steps them (Instrument::stepBodyOnce); the output is the played string's
// pickup, or the body's radiated pressure, decimated as a voice decimates its own.
RenderResult renderOnSharedBody(const Scene& scene, const RenderOptions& options)
{
    if (options.logEnergy)
        throw std::invalid_argument("the energy log of a scene with other strings on its body is the reference's "
                                    "(\"method\": \"reference\")");
    auto v = voicesOnBody(scene);
    v.body->setDelayedLink(options.bodyLinkImpedance);
    // The strings after the played one, where each is held by a spring alone, step as one bank
    // throughout, as the instrument's sympathetic strings do.
    if (v.split < static_cast<int>(v.solvers.size()))
        v.body->bankLinear(v.solvers.data(), v.split, static_cast<int>(v.solvers.size()));
    Voice& played = *v.voices[0];
    const int os = played.oversampling();
    const bool pressure = scene.pickup.quantity == PickupQuantity::pressure;
    RenderResult result;
    result.outputRateHz = scene.simulation.outputRateHz;
    auto& stats = result.stats;
    describeSolver(played.solver(), played.internalRateHz(), stats);
    Decimator decimator(os, result.outputRateHz);
    const size_t count = static_cast<size_t>(std::llround(scene.simulation.durationSeconds * result.outputRateHz));
    const size_t latency = static_cast<size_t>(decimator.latencyHostSamples());
    std::vector<double> raw(count + latency);
    std::vector<double> internal(static_cast<size_t>(os));
    ScopedFlushDenormals noDenormals;
    const double start = threadCpuSeconds();
    for (size_t m = 0; m < raw.size(); ++m)
    {
        v.stepHostSample(internal.data(), pressure);
        if (m == 0)
            decimator.prime(internal[0]);  // held before t = 0, as the reference's start
        raw[m] = decimator.process(internal.data());
        for (auto& voice : v.voices)
        {
            stats.newtonIterationsTotal += voice->takeIterationCount();
            stats.newtonIterationsMax = std::max(stats.newtonIterationsMax, voice->takeMaxIterations());
        }
        if (options.progress && m % 4096 == 0 && !options.progress(double(m) / double(raw.size())))
            throw std::runtime_error("render cancelled");
    }
    stats.cpuSeconds = threadCpuSeconds() - start;
    stats.steps = static_cast<long long>(raw.size()) * os;
    v.body->unbankLinear(v.solvers.data());
    for (const auto& voice : v.voices)
        if (voice->blowUps() > 0)
            throw std::runtime_error(lostStabilityMessage(scene.simulation, voice->blowUps()));
    result.output.assign(raw.begin() + static_cast<std::ptrdiff_t>(latency), raw.end());
    return result;
}

}  // namespace

RenderResult renderRealtime(const Scene& scene, const RenderOptions& options)
{
    auto result = scene.body && !scene.body->strings.empty() ? renderOnSharedBody(scene, options)
                                                             : renderVoice(scene, options);
    for (double v : result.output)
        if (!std::isfinite(v))
            throw std::runtime_error("the simulation produced a non-finite sample");
    return result;
}

}  // namespace jawari
