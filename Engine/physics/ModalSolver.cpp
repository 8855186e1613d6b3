#include "physics/ModalSolver.h"

#include "physics/ModalKernels.h"

#include <algorithm>
#include <cmath>
#include <limits>
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
    buildModeTables(config);
    for (auto* v : {&uC_, &uCPrev_, &uTilde_, &s_, &b_, &r_, &slope_, &penetration_, &pointForce_})
        v->assign(P_, 0.0);
    if (config.transform && P_ > 0)
        transform_ = config.transform(contacts_, lengthMetres_, M_);
    buildContactShapes(config);
    markCoupledModes(config);
    for (auto& pickup : pickups_)
        pickup.readForces(pickupForces());
    prepareContactMethods(config, stringResponse());
    pressing_.reserve(P_);
    reach_.prepare(P_, M_, config.leaveOutOfReach && !transform_ && method_ == ContactMethod::energyConserving
                               && P_ >= 2 && !system_.isDiagonal());
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
    if (config.pickupBandHz < 0.0 || !std::isfinite(config.pickupBandHz))
        throw std::invalid_argument("the pickup band must be a frequency >= 0 Hz");
    const double bandOmega = 2.0 * std::numbers::pi * config.pickupBandHz;
    std::vector<double> first = config.pickupWeights;
    first.resize(M_, 0.0);  // the first pickup is always there (its weights may all be 0)
    pickups_[0].configure(first, M_, bandOmega, P_);
    pickups_[1].configure(config.secondPickupWeights, M_, bandOmega, P_);
    for (auto& pickup : pickups_)
        pickup.setWeights(omega_, 1.0);
}

PickupReadout::Forces ModalSolver::pickupForces() const
{
    return {shapes_, excitationShape_, contacts_, forceScale_, coeffs_};
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
    for (int i = 0; i < P_; ++i)
        for (int j = 0; j < P_; ++j)
            A(i, j) = forceScale_ * contacts_[j].weight
                      * kernels::dot(&shapes_[size_t(i) * M_], &shapes_[size_t(j) * M_], M_);
    return A;
}

// The residual compliance and the chosen contact method, on the coupling A (+ C W).
void ModalSolver::prepareContactMethods(const ModalSolverConfig& config, Eigen::MatrixXd A)
{
    stringCoupling_ = A;
    compliance_.prepare(transform_ ? std::vector<double>{} : config.contactCompliance, contacts_);
    if (compliance_.active())
    {
        couplingScratch_ = A + compliance_.complianceW();
        // The contact sees the true displacement change R = r + delta^{n+1} - delta^{n-1}
        //   = (b - delta^{n-1}) + (A + C W) f: the same equation with A + C W.
        A += compliance_.complianceW();
    }
    method_ = config.method;
    pointCoupling_ = A;
    for (int j = 0; j < P_; ++j)
        pointCoupling_.col(j) /= contacts_[j].weight;
    quadratised_.prepare(P_);
    system_.prepare(contacts_, std::move(A));
    if (method_ == ContactMethod::quadraticSpline)
    {
        // Closed form per point: the points must not be coupled (one point, or the reference grid).
        if (!system_.isDiagonal())
            throw std::invalid_argument("the quadratic-spline contact needs decoupled contact points: one point, "
                                        "or a distributed obstacle on the reference grid");
        for (const auto& c : contacts_)
            splines_.emplace_back(c.law);
    }
}

void ModalSolver::setState(const std::vector<double>& current, const std::vector<double>& previous)
{
    if (static_cast<int>(current.size()) != M_ || static_cast<int>(previous.size()) != M_)
        throw std::invalid_argument("modal state has the wrong number of modes");
    state_.compact(coupled_, current, previous, excitationShape_, shapes_, P_, transform_ != nullptr,
                   !transform_ && P_ <= 1);
    state_.fillTables(coeffs_, coeffsReleased_, pickups_[0].weights(), pickups_[1].weights());
    restartFromModes();
}

void ModalSolver::restartFromModes()
{
    // Everything derived from the modal state, afresh: contact displacements, pickup, the
    // compliance deflections and the quadratised variable (xi = sqrt(2 V) at n and n-1).
    system_.reset();
    compliance_.reset();
    wakeAll();
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
    std::vector<double> previous(M_, 0.0);
    for (int p = 0; p < M_; ++p)
        previous[p] = previousAtRest(p, modalDisplacement[p]);
    setState(modalDisplacement, previous);
}

void ModalSolver::step()
{
    ScalarContactRequest request;
    if (beginStep(request))
        finishStep(solveScalarContact(request));
}

bool ModalSolver::beginStep(ScalarContactRequest& request)
{
    if (!state_.pairable() || externalForce_ != 0.0)
    {
        state_.toSingle();
        stepSingle();
        return false;
    }
    state_.beginPairs();
    predictPairStep();
    lastIterations_ = 0;
    lastPenetration_ = -std::numeric_limits<double>::infinity();
    if (P_ == 1)
    {
        s_[0] = contacts_[0].height - uCPrev_[0] - compliance_.deltaPrev(0);
        b_[0] = pairU_ - uCPrev_[0] - compliance_.deltaPrev(0);
        if (method_ == ContactMethod::energyConserving)
        {
            system_.scalarRequest(0, s_[0], b_[0], request);
            return true;
        }
        lastIterations_ = solveContacts();
    }
    finishPairStep();
    return false;
}

void ModalSolver::finishStep(const ScalarContactSolution& solution)
{
    system_.recordScalar(0, solution);
    r_[0] = solution.r;
    slope_[0] = solution.slope;
    lastIterations_ = solution.iterations;
    finishPairStep();
}

void ModalSolver::setExternalForce(double newtons)
{
    if (newtons == 0.0 && externalForce_ != 0.0)
        reach_.markStale();  // the energy the force put in
    externalForce_ = excitationShape_.empty() ? 0.0 : newtons;
}

double ModalSolver::stringEnergy() const
{
    double sum = 0.0;
    for (int i = 0; i < state_.activeCount(); ++i)
    {
        const ModalState::Mode m = state_.mode(i);
        const auto& c = state_.coefficients(i);
        const double v = (m.now - m.before) / dt_;
        sum += c.kineticWeight * v * v + c.potentialWeight * m.now * m.before;
    }
    return 0.5 * mu_ * sum;
}

double ModalSolver::obstacleEnergy() const
{
    if (method_ == ContactMethod::quadratised)
        return quadratised_.energy();
    return contactPotentialEnergy(uC_.data(), uCPrev_.data(), true);
}

// sum_j w_j (psi_j(u^n) + psi_j(u^{n-1})) / 2 for the points' displacements u at n and n-1 (with
// `liveOnly`, over the live points: the others are off their obstacle, and their u is not kept).
double ModalSolver::contactPotentialEnergy(const double* u, const double* uPrev, bool liveOnly) const
{
    auto psi = [&](int j, double penetration) {
        return method_ == ContactMethod::quadraticSpline ? splines_[size_t(j)].potential(penetration)
                                                         : contactPotential(contacts_[j].law, penetration);
    };
    double sum = 0.0;
    for (int j = 0; j < P_; ++j)
        if (!liveOnly || reach_.live(j))
            sum += contacts_[j].weight * 0.5
               * (psi(j, contacts_[j].height - u[j] - compliance_.delta(j))
                  + psi(j, contacts_[j].height - uPrev[j] - compliance_.deltaPrev(j)));
    return sum;
}

double ModalSolver::pickupCompliance(bool second) const
{
    return pickups_[second ? 1 : 0].compliance(mu_, omega_);
}

double ModalSolver::pickupAboveBand(bool second) const
{
    return pickups_[second ? 1 : 0].aboveBand(state_);
}

void ModalSolver::retune(const double* omega, const double* sigma, double complianceScale, double pickupScale)
{
    state_.toSingle();  // the paired layout's corrections were made with the old coefficients
    auto& omegas = omega_.edit();
    auto& sigmas = sigma_.edit();
    auto& coeffs = coeffs_.edit();
    auto& coeffsReleased = coeffsReleased_.edit();
    for (int p = 0; p < M_; ++p)
    {
        omegas[p] = omega[p];
        sigmas[p] = sigma[p];
        coeffs[p] = exactCoefficients(omegas[p], sigmas[p], dt_);
        coeffsReleased[p] = exactCoefficients(omegas[p], sigmas[p] + releaseSigma_, dt_);
    }
    for (auto& pickup : pickups_)
        pickup.setWeights(omega_, pickupScale);
    state_.fillTables(coeffs_, coeffsReleased_, pickups_[0].weights(), pickups_[1].weights());
    for (int k = 0; k < 2; ++k)
        if (const double* h = activePickupWeights(k))
            pickups_[size_t(k)].rereadActive(h, state_, pickupForces(), !transform_);
    if (compliance_.active())
    {
        compliance_.rescale(complianceScale, contacts_);
        updateCouplings();
    }
    measureReach();
    reach_.markStale();  // the same motion at another pitch holds another energy
}

void ModalSolver::updateCouplings()
{
    const auto& CW = compliance_.complianceW();
    for (int i = 0; i < P_; ++i)
        for (int j = 0; j < P_; ++j)
        {
            const double a = stringCoupling_(i, j) + CW(i, j);
            pointCoupling_(i, j) = a / contacts_[j].weight;
            couplingScratch_(i, j) = a;
        }
    system_.setCoupling(couplingScratch_);
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
        state_.set(i, modalDisplacement[p], previousAtRest(p, modalDisplacement[p]));
    }
    restartFromModes();
}

void ModalSolver::setContact(int j, const ContactLaw& law, double height)
{
    const bool lawChanged = contacts_[size_t(j)].law.stiffness != law.stiffness
                            || contacts_[size_t(j)].law.exponent != law.exponent;
    if (contacts_[size_t(j)].height != height)
        wakeAll();  // a sleeping point may now be within reach
    reach_.markStale();  // and the obstacles' energy is another
    contacts_[size_t(j)].law = law;
    contacts_[size_t(j)].height = height;
    system_.setLaw(j, law);
    if (method_ == ContactMethod::quadraticSpline && lawChanged)
        splines_[size_t(j)].setLaw(law);
}

void ModalSolver::displacementAt(const double* shapes, int count, double* out)
{
    state_.toSingle();
    const double* q = state_.q();
    for (int k = 0; k < count; ++k)
    {
        double u = 0.0;
        for (int i = 0; i < state_.activeCount(); ++i)
            u += q[i] * shapes[size_t(k) * M_ + state_.activeMode(i)];
        out[k] = u;
    }
}

void ModalSolver::resetToRest()
{
    state_.clear();
    externalForce_ = 0.0;
    system_.reset();
    std::fill(uC_.begin(), uC_.end(), 0.0);
    std::fill(uCPrev_.begin(), uCPrev_.end(), 0.0);
    wakeAll();
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
        const int k = other.state_.indexOfMode(state_.activeMode(i));
        state_.set(i, k >= 0 ? q[k] : 0.0, k >= 0 ? qPrev[k] : 0.0);
    }
    restartFromModes();
}

int ModalSolver::solveContacts()
{
    if (method_ == ContactMethod::energyConserving)
        return system_.solve(s_.data(), b_.data(), r_.data(), slope_.data(), reach_.liveRows(), reach_.liveCount());
    // The explicit methods start from the penetration at n.
    for (int j = 0; j < P_; ++j)
        penetration_[j] = contacts_[j].height - uC_[j] - compliance_.delta(j);
    if (method_ == ContactMethod::penalty)
        return PenaltyContact::solve(contacts_, penetration_.data(), slope_.data());
    if (method_ == ContactMethod::quadraticSpline)
        return solveSplines();
    return quadratised_.solve(contacts_, penetration_.data(), b_.data(), pointCoupling_, slope_.data());
}

// The pair's first step runs the pass over the modes for both steps (kernels::pairStep); the second
// step's contact-free projections follow from it: q~^{n+2} = Y + c1 a phi, so they gain
// c1 sum(a phi phi) and c1 sum(a phi h).
void ModalSolver::predictPairStep()
{
    if (state_.layout() == ModalState::Layout::pairBoundary)
    {
        kernels::pairStep(state_.a(), state_.e(), state_.qPrev(), state_.q(), state_.settled(), state_.h(),
                          state_.h2(), state_.singlePhi(), state_.c1(), state_.c2(), state_.paddedCount(),
                          state_.pickupCount(), pass_);
        pickups_[0].predicted = pass_.pickup1;
        pairU_ = pass_.contact1;
        pickups_[1].predicted = pass_.second1;
        return;
    }
    pickups_[0].predicted = pass_.pickup2 + state_.c1() * state_.sumAPhiH();
    pairU_ = pass_.contact2 + state_.c1() * state_.sumAPhiSquared();
    pickups_[1].predicted = pass_.second2 + state_.c1() * state_.sumAPhiH2();
}

// With the point's slope G: u_C^{n+1} = u~ + A f with f = -G, q^{n+1} = q~ + c phi with
// c = -(dt^2/mu) w G (the layout's correction), and the pickup likewise.
void ModalSolver::finishPairStep()
{
    double c = 0.0;
    if (P_ == 1)
    {
        const double G = slope_[0];
        uCPrev_[0] = uC_[0];
        uC_[0] = pairU_ - stringCoupling_(0, 0) * G;
        compliance_.advance(slope_.data());
        lastPenetration_ = contacts_[0].height - uC_[0] - compliance_.delta(0);
        c = -forceScale_ * contacts_[0].weight * G;
        for (auto& pickup : pickups_)
            pickup.press(0, G);
    }
    for (auto& pickup : pickups_)
        pickup.value = pickup.predicted;
    if (state_.layout() == ModalState::Layout::pairBoundary)
        state_.setPairMiddle(c);
    else
        state_.setPairBoundary(c);
}

// The quadratic-spline method: each point's scalar equation in closed form, on the diagonal of
// the coupling (with any residual compliance).
int ModalSolver::solveSplines()
{
    int most = 0;
    for (int j = 0; j < P_; ++j)
    {
        const auto sol = splines_[size_t(j)].solve(s_[j], b_[j], system_.coupling()(j, j));
        r_[j] = sol.r;
        slope_[j] = sol.slope;
        most = std::max(most, sol.iterations);
    }
    return most;
}

void ModalSolver::stepSingle()
{
    if (reach_.enabled())
    {
        if (externalForce_ != 0.0)
            wakeAll();
        else if (reach_.checkDue())
            refreshReach();
    }
    predictAtPoints();
    lastIterations_ = 0;
    pressing_.clear();
    if (P_ > 0)
    {
        const int* rows = reach_.liveRows();
        for (int k = 0; k < reach_.liveCount(); ++k)
        {
            const int j = rows[k];
            s_[j] = contacts_[j].height - uCPrev_[j] - compliance_.deltaPrev(j);
            b_[j] = uTilde_[j] - uCPrev_[j] - compliance_.deltaPrev(j);
        }
        lastIterations_ = solveContacts();
        for (int k = 0; k < reach_.liveCount(); ++k)
            if (slope_[rows[k]] != 0.0)
                pressing_.push_back(rows[k]);
    }
    if (!pressing_.empty())
        applyContactForces();
    endSingleStep();
}

void ModalSolver::measureReach()
{
    reach_.measure(coeffs_, coeffsReleased_, shapes_, dt_, mu_, compliance_, contacts_);
}

// H^{n-1/2} measured: a point that joins gets its u^n and u^{n-1}; one left out, no force.
void ModalSolver::refreshReach()
{
    const double H = stringEnergy() + obstacleEnergy() + compliance_.energy();
    reach_.refresh(
        H, contacts_, [this](int j) { projectPoint(j); }, [this](int j) { slope_[size_t(j)] = 0.0; });
}

void ModalSolver::wakeAll()
{
    reach_.wakeAll([this](int j) { projectPoint(j); });
}

void ModalSolver::projectPoint(int j)
{
    // Summed as the step's own projections are (kernels::projectRows).
    kernels::projectRows(state_.phi(0), state_.stride(), &j, 1, state_.q(), state_.paddedCount(), uC_.data());
    kernels::projectRows(state_.phi(0), state_.stride(), &j, 1, state_.qPrev(), state_.paddedCount(), uCPrev_.data());
}

// q~ = a q - e q^{n-1}, written over q^{n-1}, with any explicit force; its pickup and contact
// projections (the pickups' predicted readings, uTilde_).
void ModalSolver::predictAtPoints()
{
    double* next = state_.qPrev();
    const int Mpad = state_.paddedCount();
    // The first kMaxFused live points are projected in the prediction's own pass (not with an explicit
    // force, which joins q~ after it), the rest kMaxFused at a time, each sum in the same order.
    const int live = reach_.liveCount();
    const int* rows = reach_.liveRows();
    const int fused = transform_ || externalForce_ != 0.0 ? 0 : std::min(live, kernels::kMaxFused);
    auto& [first, second] = pickups_;
    if (fused > 0)
        first.predicted = kernels::predictProject(state_.a(), state_.e(), state_.q(), next, state_.h(), state_.h2(),
                                                  state_.phi(0), state_.stride(), rows, fused, Mpad,
                                                  state_.pickupCount(), uTilde_.data(), second.predicted);
    else
        first.predicted = kernels::predict(state_.a(), state_.e(), state_.q(), next, state_.h(), state_.h2(), Mpad,
                                           state_.pickupCount(), second.predicted);
    if (externalForce_ != 0.0)
    {
        // The explicit point force joins the prediction: q~ += (dt^2/mu) F phi_e.
        kernels::axpy(forceScale_ * externalForce_, state_.phiE(), next, Mpad);
        for (auto& pickup : pickups_)
            pickup.push(externalForce_);
    }
    if (transform_)
    {
        transform_->sample(next, uTilde_.data());
        return;
    }
    for (int k = fused; k < live; k += kernels::kMaxFused)
        kernels::projectRows(state_.phi(0), state_.stride(), rows + k, std::min(kernels::kMaxFused, live - k), next,
                             Mpad, uTilde_.data());
}

// q^{n+1} = q~ + (dt^2/mu) Phi^T W f with f = -G(r); u_C^{n+1} = u~ + A f at the live points, and the
// pickup likewise. Only the pressing points (pressing_) have a force.
void ModalSolver::applyContactForces()
{
    double* next = state_.qPrev();
    if (transform_)
    {
        for (int j = 0; j < P_; ++j)
            pointForce_[j] = -contacts_[j].weight * slope_[j];
        transform_->spread(pointForce_.data(), forceScale_, next);
    }
    else
        for (int i : pressing_)
            kernels::axpy(-forceScale_ * contacts_[i].weight * slope_[i], state_.phi(i), next, state_.paddedCount());
    const auto& A = stringCoupling_;
    const int* rows = reach_.liveRows();
    for (int k = 0; k < reach_.liveCount(); ++k)
    {
        const int j = rows[k];
        double Af = 0.0;
        for (int i : pressing_)
            Af -= A(j, i) * slope_[i];
        uTilde_[j] += Af;
    }
    for (int i : pressing_)
        for (auto& pickup : pickups_)
            pickup.press(i, slope_[i]);
}

// The step's end: the compliance, the live points' contact displacements and penetration, q^{n+1} as q.
void ModalSolver::endSingleStep()
{
    if (P_ > 0)
        compliance_.advance(slope_.data());
    double deepest = -std::numeric_limits<double>::infinity();  // a local: the stores below may alias a member
    const int* rows = reach_.liveRows();
    for (int k = 0; k < reach_.liveCount(); ++k)
    {
        const int j = rows[k];
        const double u = uTilde_[j];
        uCPrev_[j] = uC_[j];
        uC_[j] = u;
        deepest = std::max(deepest, contacts_[j].height - u - compliance_.delta(j));
    }
    lastPenetration_ = deepest;
    state_.swapSingle();
    for (auto& pickup : pickups_)
        pickup.value = pickup.predicted;
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

void ModalSolver::projectActive(const double* qActive, double* u) const
{
    if (P_ == 0)
        return;
    if (transform_)
    {
        transform_->sampleAside(qActive, u);
        return;
    }
    for (int j = 0; j < P_; ++j)
        u[j] = kernels::dot(state_.phi(j), qActive, state_.activeCount());
}

double ModalSolver::stepLoss(const double* next, const double* previous) const
{
    double sum = 0.0;
    for (int p = 0; p < M_; ++p)
    {
        const double v = (next[p] - previous[p]) / (2.0 * dt_);
        sum += coeffs_[p].lossWeight * v * v;
    }
    return mu_ * sum;
}

ModalSolver::Energy ModalSolver::energy()
{
    std::vector<double> current, previous;
    fullState(current, previous);
    Energy out;
    std::vector<double> u(P_), uPrev(P_);
    projectActive(current.data(), u.data());
    projectActive(previous.data(), uPrev.data());
    out.contact = contactPotentialEnergy(u.data(), uPrev.data(), false);
    if (method_ == ContactMethod::quadratised)
        out.contact = quadratised_.energy();  // the quadratised contact energy, V = xi^2/2
    if (compliance_.active())
        out.contact += compliance_.energy();  // the dropped modes' static spring
    out.total = stringEnergy() + out.contact;
    return out;
}

}  // namespace jawari
