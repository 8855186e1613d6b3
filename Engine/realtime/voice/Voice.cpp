#include "realtime/voice/Voice.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace jawari
{

namespace
{
// The sine modes a pluck's shape is given in, and that shape in the solver's modes
// (ModalSolverConfig::shapeToModes).
// One flag per obstacle: whether it stands on the voice's body (every obstacle when none are flagged).
std::vector<char> obstacleFlags(const VoiceConfig& config)
{
    return config.obstacleOnBody.empty() ? std::vector<char>(config.obstacles.size(), 1) : config.obstacleOnBody;
}

// The contact points the string can reach (g + reach > 0), and their on-the-body flags with them.
void keepReachable(std::vector<ContactPoint>& contacts, std::vector<char>& onBody,
                   const std::function<double(double)>& reach)
{
    size_t kept = 0;
    for (size_t j = 0; j < contacts.size(); ++j)
        if (contacts[j].height + reach(contacts[j].position) > 0.0)
        {
            contacts[kept] = contacts[j];
            onBody[kept++] = onBody[j];
        }
    contacts.resize(kept);
    onBody.resize(kept);
}

// The voice's body after its string's modes (withBody); the pressure pickup reads it at its listener.
void joinBody(ModalSolverConfig& c, const VoiceConfig& config, const std::vector<char>& onBody)
{
    const int stringModes = c.modes.size();
    c = withBody(c, {&*config.body, onBody, config.bodyCoupling, true});
    if (config.quantity == PickupQuantity::pressure)
    {
        c.pickupWeights = radiationWeights(*config.body, stringModes, config.string.linearDensity, config.listener);
        c.secondPickupWeights.clear();
    }
}

// The dropped modes' static compliance at the contact points (VoiceConfig::residualCompliance), and
// its loss share.
void addResidualCompliance(ModalSolverConfig& c, const VoiceConfig& config)
{
    const auto& s = config.string;
    const int M = config.modes;
    // C_ij = sum_{p > M} phi_p(x_i) phi_p(x_j) / (mu w_p^2), summed far enough that the tail is
    // below 1e-5 of the whole even for a flexible string (terms ~ 1/p^2; ~1/p^4 when stiff).
    const int P = static_cast<int>(c.contacts.size());
    const int last = M + 50000;
    const auto dropped = buildModalTable(s, last);
    c.contactCompliance.assign(size_t(P) * P, 0.0);
    std::vector<double> shape(P);
    for (int p = M + 1; p <= last; ++p)
    {
        const double w = dropped.omega[p - 1];
        const double inverseStiffness = 1.0 / (s.linearDensity * w * w);
        for (int i = 0; i < P; ++i)
            shape[i] = modeShape(s.lengthMetres, p, c.contacts[i].position);
        for (int i = 0; i < P; ++i)
            for (int j = 0; j < P; ++j)
                c.contactCompliance[size_t(i) * P + j] += shape[i] * shape[j] * inverseStiffness;
    }
    c.complianceLoss = config.residualComplianceLoss.value_or(
        residualComplianceLoss(dropped.sigma[size_t(M)], dropped.frequencyHz.front()));
}

// The contact method: a moving bridge's contact is solved again for each bridge displacement tried,
// by the methods that solve it from the step's s and b (ModalSolver::solveOnMovingBridge).
ContactMethod voiceContactMethod(const VoiceConfig& config)
{
    const bool solvesFromRequest =
        config.method == ContactMethod::energyConserving || config.method == ContactMethod::quadraticSpline;
    return config.movingBridge && !solvesFromRequest ? ContactMethod::energyConserving : config.method;
}

int shapeModes(const ModalSolverConfig& c)
{
    return c.shapeToModes.empty() ? c.modes.size() : static_cast<int>(c.shapeToModes.size()) / c.modes.size();
}

std::vector<double> shapeInModes(const ModalSolverConfig& c, const std::vector<double>& shape)
{
    if (c.shapeToModes.empty())
        return shape;
    const int N = c.modes.size(), m = static_cast<int>(shape.size());
    std::vector<double> q(static_cast<size_t>(N), 0.0);
    for (int k = 0; k < N; ++k)
        for (int p = 0; p < m; ++p)
            q[size_t(k)] += c.shapeToModes[size_t(k) * m + p] * shape[size_t(p)];
    return q;
}
}  // namespace

double residualComplianceLoss(double droppedSigma, double fundamentalHz)
{
    return std::clamp(2.0 * droppedSigma / fundamentalHz, 0.0, 1.0);
}

ModalSolverConfig voiceSolverConfig(const VoiceConfig& config)
{
    const auto& s = config.string;
    const int M = config.modes;
    if (config.quantity == PickupQuantity::bridgeForce)
        throw std::invalid_argument("the voice reads no bridge force (the reference does)");
    if (config.quantity == PickupQuantity::pressure && !config.body)
        throw std::invalid_argument("the voice reads a pressure from its body, and it has none");
    ModalSolverConfig c = stringSolverConfig(s, config.obstacles, M, config.oversampling * config.hostRateHz,
                                             config.pickupPosition, config.quantity);
    if (config.push)
    {
        ForcePluck push = *config.push;
        push.position = config.excitationPosition;
        c.excitationShape = forcePluckModalShape(s.lengthMetres, M, push);
    }
    auto onBody = contactPointsOnBody(config.obstacles, obstacleFlags(config), s.lengthMetres, M + 1);
    if (config.reach)
        keepReachable(c.contacts, onBody, config.reach);
    if (config.residualCompliance && !c.contacts.empty())
        addResidualCompliance(c, config);
    if (config.secondPickupPosition && config.quantity != PickupQuantity::force)
        c.secondPickupWeights = pickupWeights(s, c.modes, *config.secondPickupPosition, config.quantity);
    c.method = voiceContactMethod(config);
    c.pickupBandHz = config.staticPickupAboveNyquist && config.oversampling > 1 ? 0.5 * config.hostRateHz : 0.0;
    c.excitationPosition = config.excitationPosition;
    c.releaseSigma = std::log(1000.0) / config.releaseSeconds;
    c.keepEveryMode = config.keepEveryMode;
    c.staticExactForcing = config.staticExactForcing;
    if (config.secondPolarisation)
    {
        // The dropped modes' compliance at the obstacles' points stays what it is: the spring acts
        // on the kept modes only, and the compliance is between point forces and displacements.
        const auto compliance = std::move(c.contactCompliance);
        c.contactCompliance.clear();
        c = coupledModesConfig(c, *config.secondPolarisation).config;  // complianceLoss carried over
        c.contactCompliance = compliance;
    }
    if (config.body)
        joinBody(c, config, onBody);
    return c;
}

Voice::Voice(const VoiceConfig& config)
    : Voice(config, voiceSolverConfig(config))
{}

Voice::Voice(const VoiceConfig& config, const ModalSolverConfig& solverConfig)
    : VoiceMotion(Decimator(config.ownDecimator ? config.oversampling : 1, config.hostRateHz))
    , solver_(solverConfig)
    , oversampling_(config.oversampling)
    , hostRate_(config.hostRateHz)
    , quantity_(config.quantity)
    , dt_(1.0 / (config.oversampling * config.hostRateHz))
{
    baseOmega_ = solverConfig.modes.omega;
    baseFrequencyHz_ = solverConfig.modes.frequencyHz;
    baseSigma_ = solverConfig.modes.sigma;
    omegaScratch_.edit().assign(baseOmega_.size(), 0.0);
    sigmaScratch_.edit().assign(baseOmega_.size(), 0.0);
    stringModes_ = solverConfig.modes.size() - (config.body ? int(config.body->modes.size()) : 0);

    for (int j = 0; j < solver_.contactCount(); ++j)
        baseHeights_.edit().push_back(solver_.contact(j).height);
    unitPluck_ = shapeInModes(solverConfig, pluckModalShape(config.string.lengthMetres, shapeModes(solverConfig),
                                                            config.excitationPosition, 1.0));
    pluckScratch_.edit().assign(unitPluck_.size(), 0.0);
    excitationPosition_ = config.excitationPosition;
    shapesMapped_ = !solverConfig.shapeToModes.empty();
    block_.assign(oversampling_, 0.0);
    lengthMetres_ = config.string.lengthMetres;
    pickupCompliance_ = std::max(solver_.pickupCompliance(), solver_.pickupCompliance(true));
    runawayLimit_ = 0.0;
    pulseSteps_ = std::max<long>(1, std::lround((config.push ? config.push->duration : config.pluckSeconds) / dt_));
    pluckForce_ = config.push ? std::abs(config.push->amplitude) : config.pluckForceNewtons;
    if (config.push)
    {
        push_ = *config.push;
        push_->amplitude = config.push->amplitude < 0.0 ? -1.0 : 1.0;
        push_->start = 0.0;
    }
    pulseStep_ = -1;  // no pulse running
}

void Voice::setInitialShape(double position, double amplitudeMetres)
{
    if (!shapesMapped_)
        solver_.setInitialDisplacement(pluckModalShape(lengthMetres_, solver_.modeCount(), position, amplitudeMetres));
    else
    {
        // Two polarisations: unitPluck_ is the shape at the excitation point in the solver's modes.
        if (position != excitationPosition_)
            throw std::invalid_argument("a voice of two polarisations starts from its own excitation point only");
        std::vector<double> shape = unitPluck_;
        for (auto& q : shape)
            q *= amplitudeMetres;
        solver_.setInitialDisplacement(shape);
    }
    first_ = true;
    decimator_.reset();
    // A held string's velocity is 0, and its body at rest: the reset history.
    primeDecimator_ = quantity_ != PickupQuantity::velocity && quantity_ != PickupQuantity::pressure;
    raiseCeiling();
}

void Voice::pluckWithPulse(double velocity, double scale)
{
    // Scaled with the tuning (tension ~ ratio^2): the pulse moves the string as far at any pitch.
    pulsePeak_ = std::clamp(velocity, 0.0, 1.0) * pluckForce_ * ratio_ * ratio_ * scale;
    pulseStep_ = 0;
    runawayLimit_ = std::numeric_limits<double>::infinity();  // until the pulse is over (only NaN is caught)
}

void Voice::pluckFromShape(double amplitudeMetres)
{
    auto& pluck = pluckScratch_.edit();
    for (size_t p = 0; p < unitPluck_.size(); ++p)
        pluck[p] = amplitudeMetres * unitPluck_[p];
    solver_.setExternalForce(0.0);
    solver_.startFrom(pluckScratch_.data());
    decimator_.reset();
    primeDecimator_ = false;
    std::fill(block_.begin(), block_.end(), 0.0);
    first_ = true;
    pulseStep_ = -1;
    raiseCeiling();
}

void Voice::raiseCeiling()
{
    // For the displacement |u| <= sqrt(2 H G); velocity and force get the same margin on H through
    // the pickup's own weights (h^2 / (mu w^2) already carries their units squared over J). H
    // counts what the obstacles hold: a string started inside one is launched by that energy.
    energyCeiling_ = std::max(energyCeiling_, solver_.stringEnergy() + solver_.obstacleEnergy());
    runawayLimit_ = limitFor(energyCeiling_);
}

double Voice::limitFor(double ceiling) const
{
    // The modes above the pickups' band are read by their static response to the contact forces,
    // which H bounds only through the forces.
    const double forced = std::max(solver_.pickupForceBound(ceiling), solver_.pickupForceBound(ceiling, true));
    double limit = 4.0 * (std::sqrt(2.0 * ceiling * pickupCompliance_) + forced);
    if (quantity_ == PickupQuantity::velocity || quantity_ == PickupQuantity::pressure)
        limit *= 4.0 * oversampling_ * hostRate_;  // crude: |v| <= |u| omega, omega < 4 R
    return limit;
}

// Held open, the limit is infinite; let go (and no pulse of its own running), it is the ceiling's
// again, the ceiling not raised to what the string holds now.
void Voice::holdGuard(bool hold)
{
    if (hold)
        runawayLimit_ = std::numeric_limits<double>::infinity();
    else if (pulseStep_ < 0 && std::isinf(runawayLimit_))
        runawayLimit_ = limitFor(energyCeiling_);
}

void Voice::allowEnergy(double joules)
{
    if (!(joules > energyCeiling_))
        return;
    energyCeiling_ = joules;
    raiseCeiling();
}

void Voice::release()
{
    solver_.setReleased(true);
}

void Voice::cancelRelease()
{
    solver_.setReleased(false);
}

double Voice::nextInternalSample()
{
    beforeStep();
    solver_.step();
    return sampleAfterStep();
}

bool Voice::beginSample(ScalarContactRequest& request)
{
    beforeStep();
    return solver_.beginStep(request);
}

double Voice::finishSample(const ScalarContactSolution* solution)
{
    if (solution != nullptr)
        solver_.finishStep(*solution);
    return guarded(sampleAfterStep());
}

void Voice::beforeStep()
{
    if (pulseStep_ >= 0)
    {
        if (pulseStep_ < pulseSteps_)
        {
            solver_.setExternalForce(pulsePeak_ * pulseForce(pulseStep_));
            ++pulseStep_;
        }
        else
        {
            solver_.setExternalForce(0.0);
            pulseStep_ = -1;
            raiseCeiling();
        }
    }
    if (first_)
    {
        // The stream starts at u^0, like the reference's (sample n is the string at t = n dt).
        pickup_.start(solver_.pickup());
        secondPickup_.start(solver_.secondPickup());
        first_ = false;
    }
}

ModalSolver& Voice::beginOnBody()
{
    beforeStep();
    return solver_;
}

double Voice::finishOnBody()
{
    return guarded(sampleAfterStep());
}

double Voice::pulseForce(long step) const
{
    if (push_)
        return forcePluckNewtons(*push_, double(step) * dt_);
    // A raised cosine: smooth on and off, so a sounding string is plucked without a click.
    const double phase = (double(step) + 0.5) / double(pulseSteps_);
    return 0.5 * (1.0 - std::cos(2.0 * std::numbers::pi * phase));
}

double Voice::sampleAfterStep()
{
    const double yNext = solver_.pickup();
    maxIterations_ = std::max(maxIterations_, solver_.lastIterations());
    iterationCount_ += solver_.lastIterations();
    if (solver_.contactCount() > 0)
        maxPenetration_ = std::max(maxPenetration_, solver_.lastMaxPenetration());
    secondSample_ = secondPickup_.advance(solver_.secondPickup(), quantity_, dt_);
    return pickup_.advance(yNext, quantity_, dt_);
}

void Voice::process(double* out, int numSamples)
{
    assert(decimator_.factor() == oversampling_ && "Voice::process needs the voice's own decimator");
    for (int m = 0; m < numSamples; ++m)
    {
        // A held shape's history is the whole shape, the modes the pickup reads statically included.
        const double heldAboveBand = primeDecimator_ ? solver_.pickupAboveBand() : 0.0;
        for (int i = 0; i < oversampling_; ++i)
            block_[i] = nextInternalSample();
        if (primeDecimator_)
        {
            decimator_.prime(block_[0] + heldAboveBand);
            primeDecimator_ = false;
        }
        out[m] = guarded(decimator_.process(block_.data()));
    }
}

void Voice::processInternal(double* out, int numSamples, double* second)
{
    const long total = long(numSamples) * oversampling_;
    for (long k = 0; k < total; ++k)
    {
        out[k] = guarded(nextInternalSample());
        if (second != nullptr)
            second[k] = secondSample_;
    }
}

double Voice::guarded(double sample)
{
    if (std::abs(sample) <= runawayLimit_ && std::abs(secondSample_) <= runawayLimit_)  // false for NaN too
        return sample;
    // A method that lost stability (the penalty force, for one): no NaN and no blast reaches the
    // speakers; the string restarts from rest.
    ++blowUps_;
    silence();
    return 0.0;
}

void Voice::takeMotionFrom(Voice& other)
{
    solver_.takeMotionFrom(other.solver_);
    solver_.setReleased(other.solver_.released());
    // The decimators have the same factor and length: a copy of equal-sized vectors, no allocation.
    static_cast<VoiceMotion&>(*this) = other;
    if (pulseStep_ >= 0)
        runawayLimit_ = std::numeric_limits<double>::infinity();
    else if (energyCeiling_ > 0.0)
        raiseCeiling();
}

void Voice::retune(double ratio, const double* sigma, ModalSolver::RetuneMotion motion)
{
    const double previous = ratio_;
    ratio_ = ratio;
    auto& omega = omegaScratch_.edit();
    auto& damping = sigmaScratch_.edit();
    for (size_t p = 0; p < baseOmega_.size(); ++p)
    {
        const bool string = int(p) < stringModes_;
        omega[p] = string ? ratio * baseOmega_[p] : baseOmega_[p];
        damping[p] = string ? sigma[p] : baseSigma_[p];
    }
    const double pickupScale = quantity_ == PickupQuantity::force ? ratio * ratio : 1.0;
    solver_.retune(omegaScratch_.data(), sigmaScratch_.data(), 1.0 / (ratio * ratio), pickupScale, motion);
    pickupCompliance_ = std::max(solver_.pickupCompliance(), solver_.pickupCompliance(true));
    // The same motion at a higher pitch holds more energy (the tension works): the ceiling follows.
    energyCeiling_ *= std::max(1.0, (ratio * ratio) / (previous * previous));
    if (pulseStep_ < 0 && energyCeiling_ > 0.0)
        raiseCeiling();
}

void Voice::setContactLaw(const ContactLaw& law, double heightOffset)
{
    for (int j = 0; j < solver_.contactCount(); ++j)
    {
        // The damped thread keeps its own law, and holds the string at its rest line: the
        // obstacle's height moves the bridge against the string, not the string's support.
        if (!solver_.contact(j).law.bilateral)
            solver_.setContact(j, law, baseHeights_[size_t(j)] + heightOffset);
    }
    if (pulseStep_ < 0 && energyCeiling_ > 0.0)
        raiseCeiling();  // what the obstacles now hold, and the forces a stiffer law bears at that energy
}

void Voice::silence()
{
    solver_.resetToRest();
    solver_.setReleased(false);
    decimator_.reset();
    primeDecimator_ = false;
    std::fill(block_.begin(), block_.end(), 0.0);
    pickup_ = secondPickup_ = PickupStream{};
    secondSample_ = 0.0;
    first_ = true;
    pulseStep_ = -1;
    energyCeiling_ = 0.0;
    runawayLimit_ = 0.0;
}

int Voice::takeMaxIterations()
{
    const int m = maxIterations_;
    maxIterations_ = 0;
    return m;
}

long Voice::takeIterationCount()
{
    const long n = iterationCount_;
    iterationCount_ = 0;
    return n;
}

double Voice::takeMaxPenetration()
{
    const double m = maxPenetration_;
    maxPenetration_ = 0.0;
    return m;
}

}  // namespace jawari
