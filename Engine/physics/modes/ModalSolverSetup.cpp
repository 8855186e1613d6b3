// The solver's construction in stages, and its state set from outside (a pluck from a shape, a
// restart at rest, the motion taken from another solver): everything that is not a step.
#include "physics/modes/ModalSolver.h"

#include "physics/modes/ModalKernels.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <utility>

namespace jawari
{

ModalSolver::ModalSolver(const ModalSolverConfig& config)
    : M_(config.modes.size())
    , P_(static_cast<int>(config.contacts.size()))
    , dt_(config.timeStep)
    , mu_(config.linearDensity)
    , lengthMetres_(config.lengthMetres)
    , forceScale_(config.timeStep * config.timeStep / config.linearDensity)
    , contacts_(config.contacts)
{
    if (M_ < 1)
        throw std::invalid_argument("the modal solver needs at least one mode");
    if (!(dt_ > 0.0) || !(mu_ > 0.0) || !(config.lengthMetres > 0.0))
        throw std::invalid_argument("the modal solver needs a positive time step, density and length");
    if (config.staticExactForcing && config.transform)
        throw std::invalid_argument("the static-exact forcing scales the contact shapes: it takes the projection path");
    for (auto& c : contacts_)
        c.law = solverLaw(c.law, dt_);
    buildModeTables(config);
    for (auto* v : {&uC_, &uCPrev_, &uTilde_, &s_, &b_, &r_, &slope_, &penetration_, &pointForce_})
        v->assign(P_, 0.0);
    steepPrevious_.assign(size_t(M_), 0.0);
    if (config.transform && P_ > 0)
        transform_ = config.transform(contacts_, lengthMetres_, M_);
    buildContactShapes(config);
    markCoupledModes(config);
    for (auto& pickup : pickups_)
        pickup.readForces(pickupForces());
    prepareContactMethods(config, stringResponse());
    pressing_.reserve(P_);
    reach_.prepare(P_, M_,
                   config.leaveOutOfReach && !transform_ && method_ == ContactMethod::energyConserving && P_ >= 2
                       && !system_.isDiagonal());
    engaged_.prepare(P_, config.splitModes && reach_.enabled() && !compliance_.active() && P_ >= 32
                             && std::none_of(contacts_.begin(), contacts_.end(),
                                             [](const ContactPoint& c) { return c.law.bilateral; }));
    measureReach();
    if (transform_)
    {
        shapes_.edit() = std::vector<double>();  // the transform reaches the points: no table kept
    }
    setState(std::vector<double>(M_, 0.0), std::vector<double>(M_, 0.0));
}

void ModalSolver::buildModeTables(const ModalSolverConfig& config)
{
    auto& coeffs = coeffs_.edit();
    auto& coeffsReleased = coeffsReleased_.edit();
    coeffs.resize(M_);
    coeffsReleased.resize(M_);
    omega_ = config.modes.omega;
    sigma_ = config.modes.sigma;
    releaseSigma_ = config.releaseSigma;
    for (int p = 0; p < M_; ++p)
    {
        coeffs[p] = exactCoefficients(omega_[p], sigma_[p], dt_);
        coeffsReleased[p] = exactCoefficients(omega_[p], sigma_[p] + config.releaseSigma, dt_);
    }
    if (config.staticExactForcing)
    {
        modeScale_.resize(size_t(M_));
        gainRatio_.assign(size_t(M_), 1.0);
        for (int p = 0; p < M_; ++p)
            modeScale_[size_t(p)] = std::sqrt(staticForcingGain(omega_[p], sigma_[p], dt_));
    }
    if (config.pickupBandHz < 0.0 || !std::isfinite(config.pickupBandHz))
        throw std::invalid_argument("the pickup band must be a frequency >= 0 Hz");
    const double bandOmega = 2.0 * std::numbers::pi * config.pickupBandHz;
    std::vector<double> first = config.pickupWeights;
    first.resize(M_, 0.0);  // the first pickup is always there (its weights may all be 0)
    std::vector<double> second = config.secondPickupWeights;
    scaleByModes(first.data(), int(first.size()), modeScale_);
    scaleByModes(second.data(), int(second.size()), modeScale_);
    pickups_[0].configure(first, M_, bandOmega, P_);
    pickups_[1].configure(second, M_, bandOmega, P_);
    for (auto& pickup : pickups_)
        pickup.setWeights(omega_, 1.0);
}

// phi_p(x_j) for every point and mode.
void ModalSolver::buildContactShapes(const ModalSolverConfig& config)
{
    if (!config.contactShapes.empty())
    {
        if (config.contactShapes.size() != static_cast<size_t>(P_) * M_ || config.transform)
            throw std::invalid_argument("the contact shapes must be P x M values, on the projection path");
        shapes_ = config.contactShapes;
    }
    else
    {
        auto& shapes = shapes_.edit();
        shapes.resize(static_cast<size_t>(P_) * M_);
        for (int j = 0; j < P_; ++j)
            for (int p = 0; p < M_; ++p)
                shapes[size_t(j) * M_ + p] = modeShape(config.lengthMetres, p + 1, contacts_[j].position);
    }
    if (!modeScale_.empty())
    {
        auto& shapes = shapes_.edit();
        for (int j = 0; j < P_; ++j)
            scaleByModes(shapes.data() + size_t(j) * M_, M_, modeScale_);
    }
}

// A mode is coupled when some contact point, or the excitation point, sees it above rounding
// (|phi| <= sqrt(2/L)); the transform path and keepEveryMode step every mode.
void ModalSolver::markCoupledModes(const ModalSolverConfig& config)
{
    const double L = config.lengthMetres;
    auto& coupled = coupled_.edit();
    coupled.assign(M_, transform_ || config.keepEveryMode ? 1 : 0);
    const double couplingFloor = 1e-13 * std::sqrt(2.0 / L);
    for (int j = 0; j < P_; ++j)
        for (int p = 0; p < M_; ++p)
            if (std::abs(shapes_[size_t(j) * M_ + p]) > couplingFloor)
                coupled[p] = 1;
    if (config.excitationPosition)
    {
        if (!config.excitationShape.empty() && static_cast<int>(config.excitationShape.size()) != M_)
            throw std::invalid_argument("the excitation shape must have one value per mode");
        auto& excitationShape = excitationShape_.edit();
        excitationShape.resize(M_);
        for (int p = 0; p < M_; ++p)
        {
            excitationShape[p] = config.excitationShape.empty() ? modeShape(L, p + 1, *config.excitationPosition)
                                                                : config.excitationShape[size_t(p)];
            if (std::abs(excitationShape[p]) > couplingFloor)
                coupled[p] = 1;
        }
        scaleByModes(excitationShape.data(), M_, modeScale_);
    }
}

// A = (dt^2/mu) Phi Phi^T W, the string's response at the points. On the grid with M = N - 1,
// S dx S^T = I, so Phi Phi^T W = diag(w_j / dx).
Eigen::MatrixXd ModalSolver::stringResponse() const
{
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(P_, P_);
    if (transform_)
    {
        const double dx = lengthMetres_ / (M_ + 1);
        for (int j = 0; j < P_; ++j)
            A(j, j) = forceScale_ * contacts_[j].weight / dx;
        return A;
    }
    fillStringResponse(A);
    return A;
}

void ModalSolver::fillStringResponse(Eigen::MatrixXd& A) const
{
    for (int i = 0; i < P_; ++i)
        for (int j = 0; j < P_; ++j)
            A(i, j) = forceScale_ * contacts_[j].weight
                      * kernels::dot(&shapes_[size_t(i) * M_], &shapes_[size_t(j) * M_], M_);
}

// The residual compliance and the chosen contact method, on the coupling A (+ kappa C W).
void ModalSolver::prepareContactMethods(const ModalSolverConfig& config, Eigen::MatrixXd A)
{
    stringCoupling_ = A;
    compliance_.prepare(transform_ ? std::vector<double>{} : config.contactCompliance, contacts_,
                        config.complianceLoss);
    if (compliance_.active())
    {
        couplingScratch_ = A + compliance_.coupling();
        // The contact sees the true displacement change R = r + delta^{n+1} - delta^{n-1}
        //   = (b - kappa delta^{n-1}) + (A + kappa C W) f: the same equation with A + kappa C W.
        A += compliance_.coupling();
    }
    else if (!modeScale_.empty())
        couplingScratch_ = A;  // a retune forms A again (followStaticGains, updateCouplings)
    method_ = config.method;
    pointCoupling_ = A;
    for (int j = 0; j < P_; ++j)
        pointCoupling_.col(j) /= contacts_[j].weight;
    quadratised_.prepare(P_);
    system_.prepare(contacts_, std::move(A));
    findSpringPoint();
    if (method_ == ContactMethod::quadraticSpline)
    {
        // Closed form per point: the points must not be coupled (one point, or the reference grid).
        if (!system_.isDiagonal())
            throw std::invalid_argument("the quadratic-spline contact needs decoupled contact points: one point, "
                                        "or a distributed obstacle on the reference grid");
        for (const auto& c : contacts_)
            splines_.emplace_back(c.law);  // a bilateral point's stays unused: its equation is linear
    }
}

void ModalSolver::setState(const std::vector<double>& current, const std::vector<double>& previous)
{
    if (static_cast<int>(current.size()) != M_ || static_cast<int>(previous.size()) != M_)
        throw std::invalid_argument("modal state has the wrong number of modes");
    state_.compact(coupled_, current, previous, excitationShape_, shapes_, P_, transform_ != nullptr,
                   !transform_ && P_ <= 1);
    state_.fillTables(coeffs_, coeffsReleased_, pickups_[0].weights(), pickups_[1].weights());
    measureTail();  // over the active modes
    restartFromModes();
}

void ModalSolver::restartFromModes()
{
    // Everything derived from the modal state, afresh: contact displacements, pickup, the
    // compliance deflections and the quadratised variable (xi = sqrt(2 V) at n and n-1).
    system_.reset();
    compliance_.reset();
    wakeAll();
    engaged_.engageAll();
    projectActive(state_.q(), uC_.data());
    projectActive(state_.qPrev(), uCPrev_.data());
    for (int k = 0; k < 2; ++k)
        pickups_[size_t(k)].read(activePickupWeights(k), state_);
    if (method_ == ContactMethod::quadratised)
        quadratised_.restart(contacts_, uC_.data(), uCPrev_.data());
}

void ModalSolver::setInitialDisplacement(const std::vector<double>& modalDisplacement)
{
    if (static_cast<int>(modalDisplacement.size()) != M_)
        throw std::invalid_argument("initial displacement has the wrong number of modes");
    // q^{-1} is the exact free motion one step back, so a run without contact is the analytic
    // solution. For a mode damped by more than e^0.5 per step that value is huge (e^{sigma dt}: the
    // top modes of a fine grid at an audio rate reach e^26) and the recurrence would cancel huge
    // numbers; such a mode starts at rest in the centred sense instead, q^{-1} = q(+dt).
    std::vector<double> current(modalDisplacement), previous(M_, 0.0);
    for (int p = 0; p < M_; ++p)
    {
        current[p] = toSolverCoordinate(p, current[p]);
        previous[p] = previousAtRest(p, current[p]);
    }
    setState(current, previous);
}

double ModalSolver::previousAtRest(int p, double q0) const
{
    const double back = sigma_[p] * dt_ <= 0.5 ? -dt_ : dt_;  // see setInitialDisplacement()
    return freeDampedMotion(q0, 0.0, omega_[p], sigma_[p], back);
}

void ModalSolver::startFrom(const double* modalDisplacement)
{
    state_.restartSingle();
    for (int i = 0; i < state_.activeCount(); ++i)
    {
        const int p = state_.activeMode(i);
        const double now = toSolverCoordinate(p, modalDisplacement[p]);
        state_.set(i, now, previousAtRest(p, now));
    }
    restartFromModes();
}

void ModalSolver::resetToRest()
{
    state_.clear();
    externalForce_ = 0.0;
    system_.reset();
    std::fill(uC_.begin(), uC_.end(), 0.0);
    std::fill(uCPrev_.begin(), uCPrev_.end(), 0.0);
    wakeAll();
    engaged_.engageAll();
    compliance_.reset();
    quadratised_.reset();
    for (auto& pickup : pickups_)
        pickup.value = pickup.predicted = 0.0;
}

void ModalSolver::takeMotionFrom(ModalSolver& other)
{
    other.state_.toSingle();
    state_.toSingle();
    const double* q = other.state_.q();
    const double* qPrev = other.state_.qPrev();
    for (int i = 0; i < state_.activeCount(); ++i)
    {
        const int p = state_.activeMode(i);
        const int k = other.state_.indexOfMode(p);
        state_.set(i, k >= 0 ? toSolverCoordinate(p, other.toModeCoordinate(p, q[k])) : 0.0,
                   k >= 0 ? toSolverCoordinate(p, other.toModeCoordinate(p, qPrev[k])) : 0.0);
    }
    restartFromModes();
}

void ModalSolver::fullState(std::vector<double>& current, std::vector<double>& previous) const
{
    // Active-mode state (q^n, q^{n-1}), whatever the layout.
    const int Ma = state_.activeCount();
    current.resize(Ma);
    previous.resize(Ma);
    for (int i = 0; i < Ma; ++i)
    {
        const ModalState::Mode m = state_.mode(i);
        current[i] = m.now;
        previous[i] = m.before;
    }
}

std::vector<double> ModalSolver::modalState(bool previous)
{
    std::vector<double> current, before;
    fullState(current, before);
    std::vector<double> full(M_, 0.0);
    const auto& src = previous ? before : current;
    for (int i = 0; i < state_.activeCount(); ++i)
        full[state_.activeMode(i)] = src[i];
    return full;
}

}  // namespace jawari
