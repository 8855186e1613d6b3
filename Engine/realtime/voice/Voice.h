#pragma once
// The real-time voice (docs/design.md section 2, "The real-time voice"; section 5): M truncated modes,
// contact points only where obstacles are, an internal rate R = oversampling x host rate, and a
// decimator to the host rate. What the plugin plays and `jawari-render --method realtime` runs.
//
// Construction is OFF (tables, contact matrices, filter design). The plucks, release(), process()
// and takeMotionFrom() are RT: no allocation, no locks, no I/O.

#include "physics/string/ForcePluck.h"
#include "physics/body/ModalBody.h"
#include "physics/modes/ModalSolver.h"
#include "physics/contact/Obstacle.h"
#include "physics/string/Polarisations.h"
#include "physics/modes/StampedVector.h"
#include "physics/string/StringDiscretisation.h"
#include "physics/string/StringModel.h"
#include "realtime/voice/Decimator.h"

#include <functional>
#include <optional>
#include <utility>
#include <vector>

namespace jawari
{

struct VoiceConfig
{
    StringParameters string;
    std::vector<Obstacle> obstacles;
    double excitationPosition = 0.501;  // where the plucks act (m)
    double pickupPosition = 0.992;      // m
    PickupQuantity quantity = PickupQuantity::displacement;
    // A second pickup (m), read beside the first: the instrument's right channel. Displacement or
    // velocity only (the force is read at the termination). Empty: none.
    std::optional<double> secondPickupPosition;
    int modes = 200;       // M
    int oversampling = 8;  // R / host rate
    double hostRateHz = 48000.0;
    double releaseSeconds = 0.25;    // note-off: every mode gains damping ln(1000)/releaseSeconds
    double pluckSeconds = 1.5e-3;    // the pluck's force pulse (raised cosine) lasts this long
    double pluckForceNewtons = 2.0;  // its peak force at velocity 1
    // DAFx-16's push instead of the pulse (ForcePluck.h: it rises slowly and lets go abruptly, spread
    // over its width around the excitation point), its amplitude per unit velocity. A finger's
    // pluck, whose sound through a body grows (docs/design.md section 1, "The body"). Empty: the pulse.
    std::optional<ForcePluck> push;
    // The dropped modes' static compliance in series with the contact (docs/design.md section 5). Off,
    // the voice is plain truncation (and equals the reference when M = N - 1).
    bool residualCompliance = true;
    // Each mode answers a force by its exact static compliance (ModalSolverConfig::staticExactForcing);
    // off, the paper's gain dt^2/mu for every mode.
    bool staticExactForcing = false;
    // Its loss share theta (ModalSolverConfig::complianceLoss). Empty: residualComplianceLoss().
    std::optional<double> residualComplianceLoss;
    // The pickups read the modes above the host's Nyquist frequency by their static response to the
    // forces (ModalSolverConfig::pickupBandHz), which the decimator passes; their ringing it stops.
    // Off, or without oversampling, the pickups read every mode as it moves.
    bool staticPickupAboveNyquist = true;
    ContactMethod method = ContactMethod::energyConserving;
    // The voice decimates its own output (process()). Off for a voice whose internal-rate samples a
    // caller mixes before one decimator per channel (the instrument's: processInternal() only):
    // it then carries no filter, and a copy of it (the second core's backup) is a third smaller.
    bool ownDecimator = true;
    // Step every mode (see ModalSolverConfig::keepEveryMode): the plugin's voices.
    bool keepEveryMode = false;
    // The string's second polarisation, its coupling folded into the modes (coupledModesConfig):
    // 2M modes. The obstacles act on the vertical, the pickups read it, the plucks push along the
    // excitation angle. Empty: one polarisation.
    std::optional<SecondPolarisation> secondPolarisation;
    // How far the string can ever move at x (m), when known (a scene plucked once: reachAt in
    // Quality.h): contact points with g + reach <= 0 are left out. Empty: every point is kept.
    std::function<double(double)> reach;
    // The body under the obstacles flagged in obstacleOnBody (one flag per obstacle; empty: every
    // obstacle), its modes after the string's (ModalBody.h), coupled by bodyCoupling. The "pressure"
    // quantity reads its radiated sound at `listener` (ModalBody::listeners). Empty: rigid supports.
    std::optional<ModalBody> body;
    int listener = 0;
    std::vector<char> obstacleOnBody;
    double bodyCoupling = 1.0;
    // Its obstacles stand on a body stepped beside it (SharedBody, the instrument's): the contacts
    // take the energy-conserving method or the quadratic spline, and the body chooses their live points.
    bool movingBridge = false;
};

// A voice's motion beyond its solver's: what Voice::takeMotionFrom() carries over to a voice of the
// same string, copied as a whole (a member added here cannot be left out of that copy).
struct VoiceMotion
{
    // The stream of one pickup: sample n is the string at t = n dt (displacement), or the centred
    // difference around it (velocity, and the body's pressure).
    struct PickupStream
    {
        double y = 0.0, previous = 0.0;
        void start(double value) { y = previous = value; }
        double advance(double next, PickupQuantity quantity, double dt)
        {
            const bool rate = quantity == PickupQuantity::velocity || quantity == PickupQuantity::pressure;
            const double sample = rate ? (next - previous) / (2.0 * dt) : y;
            previous = y;
            y = next;
            return sample;
        }
    };

    explicit VoiceMotion(Decimator decimator)
        : decimator_(std::move(decimator))
    {}

    Decimator decimator_;
    PickupStream pickup_, secondPickup_;
    double secondSample_ = 0.0;
    bool first_ = true;
    bool primeDecimator_ = false;  // the next host sample's first internal sample fills the history
    // Pluck pulse: the step within it, or -1 when none is running.
    long pulseStep_ = -1;
    double pulsePeak_ = 0.0;
    double energyCeiling_ = 0.0;  // the most energy the string has legitimately had (blowUps())
};

class Voice : private VoiceMotion
{
public:
    explicit Voice(const VoiceConfig& config);  // OFF
    // OFF: with the solver configuration already built (voiceSolverConfig(config)): several voices
    // of one string share the work of building it.
    Voice(const VoiceConfig& config, const ModalSolverConfig& solverConfig);
    Voice(const Voice&) = delete;
    // RT: this voice becomes the other's exact copy (its string, state, pulse, counters, tables).
    // Only into a voice built from the same configuration: then nothing is allocated.
    Voice& operator=(const Voice&) = default;

    int modes() const { return solver_.modeCount(); }
    int activeModes() const { return solver_.activeModeCount(); }
    int contactPoints() const { return solver_.contactCount(); }
    int oversampling() const { return oversampling_; }
    double internalRateHz() const { return oversampling_ * hostRate_; }
    int latencySamples() const { return decimator_.latencyHostSamples(); }  // host samples; 0 without its own decimator

    // OFF: the string at rest in the triangular shape of the given amplitude at x (the scene's
    // pluck), as the reference starts: held there before t = 0, so the decimator's history is the
    // held string's first sample (OfflineRender treats the reference's resampling the same way).
    void setInitialShape(double position, double amplitudeMetres);

    // RT: a force pulse at the excitation point, its force times `scale`; works while sounding.
    void pluckWithPulse(double velocity, double scale = 1.0);
    bool pushes() const { return push_.has_value(); }  // its pulse is DAFx-16's push (VoiceConfig::push)
    bool pulsing() const { return pulseStep_ >= 0; }   // a pluck's pulse or push is running
    // RT: the string released from the triangular shape of the given amplitude (m) at the
    // excitation point: the paper's pluck (setInitialShape() without allocating). From rest only:
    // whatever the string was doing is replaced.
    void pluckFromShape(double amplitudeMetres);
    void release();                             // RT: note-off, the string rings down over releaseSeconds
    void cancelRelease();                       // RT: back to the string's own damping (a new note)
    // RT: numSamples host samples of the pickup quantity. Only with its own decimator.
    void process(double* out, int numSamples);
    // RT: the same motion at the internal rate, undecimated: oversampling() samples per host sample,
    // numSamples host samples' worth, for a caller that mixes strings before one decimator per
    // channel (the decimator is linear). The same guard as process(), sample by sample.
    // With a second pickup, its samples go to `second` (when not null), guarded with the first's.
    void processInternal(double* out, int numSamples, double* second = nullptr);
    void takeMotionFrom(Voice& other);  // RT: same string and modes, new obstacles/contact
    // RT: one sample of processInternal() in two halves around the contact solve, for the string
    // bank, which solves many strings' points together. beginSample() returns true when the step
    // waits for its point's solution to `request`: finishSample() then takes it (else nullptr) and
    // returns the guarded internal sample.
    bool beginSample(ScalarContactRequest& request);
    double finishSample(const ScalarContactSolution* solution);
    double secondSample() const { return secondSample_; }  // RT: the second pickup's, of the last sample
    // RT: one internal sample on a shared body (SharedBody::step between the two): the pulse's force
    // set and the solver handed over, then the guarded sample.
    ModalSolver& beginOnBody();
    double finishOnBody();

    // RT: every string mode's frequency scaled by `ratio` from the configured string (the note's pitch:
    // tension and bending stiffness scaled together, so the inharmonicity B stays), and the damping
    // sigma (1/s, at least the string's modes' values) given for the new frequencies. The residual
    // compliance follows (1/r^2). A body's modes keep their own. `motion`: as ModalSolver::retune
    // (keepActions for a string whose pitch moves while it sounds).
    void retune(double ratio, const double* sigma,
                ModalSolver::RetuneMotion motion = ModalSolver::RetuneMotion::keepState);
    double tuningRatio() const { return ratio_; }
    // The configured modes' frequencies (Hz), before any retune.
    const std::vector<double>& baseFrequencies() const { return baseFrequencyHz_; }
    // RT: the obstacles' law and a height offset (m) from their configured heights, every contact point.
    void setContactLaw(const ContactLaw& law, double heightOffset);
    // RT: the string's energy (J) without the contact part.
    double stringEnergy() const { return solver_.stringEnergy(); }
    // RT: the string at rest, output and pulse cleared (a stolen voice before its new note).
    void silence();

    // RT: how many times the voice found its output non-finite or running away and put the string
    // back at rest, muting instead of sending it on. Running away: beyond 4 sqrt(2 H G), with G the
    // static compliance seen by the pickup and H the most energy the string has legitimately had
    // (measured after the initial shape and after each pluck pulse): no physical motion gets there.
    long blowUps() const { return blowUps_; }
    // The level beyond which a sample counts as running away (above); infinite during a pluck pulse.
    double runawayLimit() const { return runawayLimit_; }
    double energyCeiling() const { return energyCeiling_; }  // H above (J)
    // RT: H raised to `joules` (when above it): the energy a string that is never plucked (a
    // sympathetic one) may legitimately take from the strings that are.
    void allowEnergy(double joules);
    // RT: the runaway guard held open (a string on a body while another's pluck is still putting in
    // energy that no ceiling counts yet), or back at the ceiling.
    void holdGuard(bool hold);

    // RT: the most Newton iterations of one internal step, and the deepest penetration (m),
    // since the last call.
    int takeMaxIterations();
    long takeIterationCount();  // RT: Newton iterations summed over the internal steps since the last call
    double takeMaxPenetration();
    ModalSolver& solver() { return solver_; }

private:
    double nextInternalSample();
    void beforeStep();        // the pluck pulse's force and the stream's first sample
    double sampleAfterStep();  // the step's output sample and statistics
    // The sample, or 0 after a restart when it (or the second pickup's) is beyond the runaway limit.
    double guarded(double sample);

    ModalSolver solver_;
    int oversampling_ = 1;
    double hostRate_ = 48000.0;
    PickupQuantity quantity_ = PickupQuantity::displacement;
    double dt_ = 0.0;
    double lengthMetres_ = 1.0;
    std::vector<double> block_;  // one host sample's internal samples
    long pulseSteps_ = 0;  // the pluck pulse's length
    double pluckForce_ = 0.0;
    std::optional<ForcePluck> push_;  // the push's shape in time (VoiceConfig::push), amplitude 1
    double pulseForce(long step) const;  // the pulse's force at a step, per newton of its peak
    long blowUps_ = 0;
    double runawayLimit_ = 1.0;
    double pickupCompliance_ = 0.0;
    void raiseCeiling();
    double limitFor(double ceiling) const;  // the runaway limit for a string whose H is at most `ceiling`
    int maxIterations_ = 0;
    long iterationCount_ = 0;
    double maxPenetration_ = 0.0;
    double ratio_ = 1.0;
    // Tables, and scratch the RT calls fill before use: skipped by a copy that has them already.
    StampedVector<double> baseOmega_, baseFrequencyHz_, omegaScratch_, baseHeights_;
    StampedVector<double> baseSigma_, sigmaScratch_;  // every mode's configured damping; retune()'s
    int stringModes_ = 0;  // the modes a retune scales: the string's (a body's modes follow them)
    StampedVector<double> unitPluck_, pluckScratch_;  // the 1 m triangular pluck's modal shape
    double excitationPosition_ = 0.0;
    bool shapesMapped_ = false;  // the solver's modes are not the sine modes (two polarisations, a body)
};

// The voice's solver: stringSolverConfig plus the excitation point, the release damping, the
// contact method and the residual compliance. OFF.
ModalSolverConfig voiceSolverConfig(const VoiceConfig& config);

// The residual compliance's loss share theta for a string whose first dropped mode decays at
// `droppedSigma` (1/s) and whose first mode sounds at fundamentalHz: the share of its energy that
// mode loses in one period of the fundamental, 2 sigma / f1, at most 1. The energy the contact puts
// into the dropped modes comes back at the next contact if they keep it, and is gone if they lose
// it first: 0 for a lossless string, whose voice then conserves its energy exactly; 1 (backward
// Euler) for the strings of every preset (Valette's law, and DAFx-16's by wavenumber, lose far
// more); 0.009 for DAFx-16's C3 string at a constant 0.6 /s, whose buzz band theta = 1 made fall
// (to 0.56 of its early centroid by 1 s) where the reference's holds (1.00; now 0.91, and 1.67 at
// theta = 0). Measured against the reference on every preset scene, theta = 1 is
// the closer there: the trapezoid (theta near 0) keeps a spurious ringing of the spring at a
// quarter of the internal rate, which the contact feels (docs/design.md section 5).
double residualComplianceLoss(double droppedSigma, double fundamentalHz);

}  // namespace jawari
