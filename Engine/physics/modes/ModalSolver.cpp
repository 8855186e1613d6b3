// The solver's step, in its two forms (one pass per step; two steps per pass with one point), its
// automation (retune, contact law, force) and its energy. Construction and state set-up: ModalSolverSetup.cpp.
#include "physics/modes/ModalSolver.h"

#include "physics/modes/ModalKernels.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <utility>

namespace jawari
{

void ModalSolver::step()
{
    ScalarContactRequest request;
    if (beginStep(request))
        finishStep(solveScalarContact(request));
}

bool ModalSolver::beginStep(ScalarContactRequest& request)
{
    system_.beginStep();
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
        b_[0] = pairU_ - uCPrev_[0] - compliance_.restoring(0);
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

// A string with one point or none and no explicit force takes the paired path (two steps per pass
// over the modes), as step() does: the point's predicted displacement is then pairU_.
void ModalSolver::predictOnMovingBridge()
{
    lastIterations_ = 0;
    trialBefore_ = trialMove_ = std::numeric_limits<double>::quiet_NaN();  // no trial of this step yet
    system_.beginStep();
    pairedOnBridge_ = state_.pairable() && externalForce_ == 0.0;
    if (pairedOnBridge_)
    {
        state_.beginPairs();
        predictPairStep();
        lastPenetration_ = -std::numeric_limits<double>::infinity();
        return;
    }
    state_.toSingle();
    if (engaged_.anyOut())
        engageEveryPoint();  // a split step's points out (never on a body: EngagedPoints)
    if (reach_.liveCount() < P_)
        keepSteepPrevious();
    predictAtPoints();
}

double ModalSolver::solveOnMovingBridge(double before, double move)
{
    pressing_.clear();
    lastSolveWasTrial_ = false;
    if (P_ == 0)
        return 0.0;
    const int* rows = reach_.liveRows();
    for (int k = 0; k < reach_.liveCount(); ++k)
    {
        const int j = rows[k];
        s_[j] = sOnBridge(j, before);
        b_[j] = bOnBridge(j, move);
    }
    if (loneSpring() && !(before == trialBefore_ && move == trialMove_))
    {
        // Its linear equation in closed form, as the solve below would pose and solve it (the same
        // bits), without the contact system's general path.
        const auto solved = solveScalarContact(contacts_[0].law, s_[0], b_[0], system_.coupling()(0, 0));
        system_.recordScalar(0, solved);
        r_[0] = solved.r;
        slope_[0] = solved.slope;
    }
    else if (springPoint_ >= 0 && springTrialPresser_ >= -1 && before == trialBefore_ && move == trialMove_)
    {
        // The step's last trial was this string's solve: the spring and its other point. Kept once.
        system_.recordSpringTrial(springPoint_, springTrialPresser_, springTrial_, r_.data(), slope_.data());
        lastIterations_ += springTrial_.a.iterations;
        trialBefore_ = trialMove_ = std::numeric_limits<double>::quiet_NaN();
        lastSolveWasTrial_ = true;
    }
    else if (P_ == 1 && before == trialBefore_ && move == trialMove_)
    {
        // The step's last trial posed this very equation (a string's one point): its solution is
        // the solve's, kept as solveContacts() keeps one.
        r_[0] = trial_.r;
        slope_[0] = trial_.slope;
        if (method_ == ContactMethod::energyConserving)
            system_.recordScalar(0, trial_);
        lastIterations_ += trial_.iterations;
        lastSolveWasTrial_ = true;
    }
    else
    {
        // A string of several points takes its last trial where the solve poses that same equation
        // (ContactSystem::solveAlone).
        lastIterations_ += solveContacts();
        lastSolveWasTrial_ = method_ == ContactMethod::energyConserving && system_.tookTrial();
    }
    double force = 0.0;
    for (int k = 0; k < reach_.liveCount(); ++k)
        if (const int j = rows[k]; slope_[j] != 0.0)
        {
            pressing_.push_back(j);
            force += contacts_[j].weight * slope_[j];
        }
    return force;
}

// Point j pressing alone with G' = g at its root: r + k G(r) = b with db/dmove = -1, so
// dr/dmove = -1 / (1 + k g), and F = w G.
double ModalSolver::aloneForceSlope(int j, double g) const
{
    return -contacts_[size_t(j)].weight * g / (1.0 + system_.coupling()(j, j) * g);
}

// G'_j at point j's root in the last solve (NaN where it has no closed form).
double ModalSolver::solvedSlopeDerivative(int j) const
{
    if (method_ == ContactMethod::quadraticSpline && !contacts_[size_t(j)].law.bilateral)
        return splines_[size_t(j)].solve(s_[j], b_[j], system_.coupling()(j, j)).slopeDerivative;
    ScalarContactSolution at;
    at.r = r_[j];
    at.slope = slope_[j];
    return chordSlopeDerivative(contacts_[size_t(j)].law, s_[j], at);
}

// F = sum_j w_j G_j(r_j) over the pressing points P, r solving r + A G(r) = b: dr/dmove = -(I + A_PP D)^-1 1
// with D = diag(G'_j), so dF/dmove = -w^T D (I + A_PP D)^-1 1.
double ModalSolver::solvedForceSlope() const
{
    const int n = static_cast<int>(pressing_.size());
    if (n == 0)
        return 0.0;
    if (n == 1)
        return aloneForceSlope(pressing_[0], solvedSlopeDerivative(pressing_[0]));
    if (n > kMostSlopePoints || method_ != ContactMethod::energyConserving)
        return std::numeric_limits<double>::quiet_NaN();
    using Small = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMostSlopePoints, kMostSlopePoints>;
    using SmallVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMostSlopePoints, 1>;
    Small J(n, n);
    SmallVector wD(n);
    const auto& A = system_.coupling();
    for (int l = 0; l < n; ++l)
    {
        const int j = pressing_[size_t(l)];
        const double g = solvedSlopeDerivative(j);
        if (!std::isfinite(g))
            return std::numeric_limits<double>::quiet_NaN();
        wD[l] = contacts_[size_t(j)].weight * g;
        for (int m = 0; m < n; ++m)
            J(m, l) = A(pressing_[size_t(m)], j) * g + (m == l ? 1.0 : 0.0);
    }
    return -wD.dot(J.partialPivLu().solve(SmallVector::Ones(n)));
}

double ModalSolver::trialOnMovingBridge(double before, double move, double* slope) const
{
    int j = 0;  // a string's one point: its scalar equation is its solve, the trial exact
    if (slope != nullptr)
        *slope = 0.0;
    if (P_ > 1 && springPoint_ >= 0)
        return trialWithSpring(before, move, slope);
    if (springsUntried_)
        return std::numeric_limits<double>::quiet_NaN();  // a spring pulls even at rest: only a solve tells
    if (P_ == 0 || (P_ > 1 && pressing_.empty()))
        return 0.0;
    if (P_ > 1)
    {
        j = pressing_[0];
        if (pressing_.size() > 1 || contacts_[j].law.bilateral)
            return std::numeric_limits<double>::quiet_NaN();
    }
    const double s = sOnBridge(j, before), b = bOnBridge(j, move);
    // A lone spring's linear equation in closed form, without the contact system's trial bookkeeping.
    const auto solution =
        loneSpring() ? solveScalarContact(contacts_[0].law, s, b, system_.coupling()(0, 0)) : solvePointAlone(j, s, b);
    if (slope != nullptr)
        *slope = aloneForceSlope(j, chordSlopeDerivative(contacts_[j].law, s, solution));
    if (P_ == 1)
    {
        trial_ = solution;
        trialBefore_ = before;
        trialMove_ = move;
    }
    return contacts_[j].weight * solution.slope;
}

// A string held by one spring (a bilateral point: the damped thread, a sympathetic string's bridge)
// beside points that can touch: the spring and the one other point that presses (a string with two
// points: its other one, whatever it did before, so the trial is its solve), by the Schur complement
// of ContactSystem::solveWithBilateral. NaN if two others pressed at the last solve.
double ModalSolver::trialWithSpring(double before, double move, double* slope) const
{
    const int t = springPoint_;
    int a = -1;
    for (int j = 0; j < P_; ++j)
        if (j != t && (P_ == 2 || std::find(pressing_.begin(), pressing_.end(), j) != pressing_.end()))
        {
            if (a >= 0)
                return std::numeric_limits<double>::quiet_NaN();
            a = j;
        }
    if (a >= 0 && !reach_.live(a))
        a = -1;  // out of reach: it stays off whatever the bridge does this step
    const auto trial = system_.trialWithSpring(t, a, sOnBridge(t, before), bOnBridge(t, move),
                                               a >= 0 ? sOnBridge(a, before) : 0.0, a >= 0 ? bOnBridge(a, move) : 0.0);
    const double wt = contacts_[t].weight, wa = a >= 0 ? contacts_[a].weight : 0.0;
    if (slope != nullptr)
        *slope = -(wt * trial.dGt + wa * trial.dGa);  // b falls by one per metre the bridge moves
    if (P_ == 2)
    {
        // Its solve: kept, so that the step's solve at this bridge takes it (solveOnMovingBridge).
        springTrial_ = trial;
        springTrialPresser_ = a;
        trialBefore_ = before;
        trialMove_ = move;
    }
    return wt * trial.Gt + wa * trial.Ga;
}

double ModalSolver::sOnBridge(int j, double before) const
{
    return contacts_[j].height + before - uCPrev_[j] - compliance_.deltaPrev(j);
}

double ModalSolver::bOnBridge(int j, double move) const
{
    const double predicted = pairedOnBridge_ ? pairU_ : uTilde_[j];
    return predicted - uCPrev_[j] - compliance_.restoring(j) - move;
}

// The spline's potential, or the law's (a bilateral point's, whose equation is linear), through the
// contact system's coupling at j.
ScalarContactSolution ModalSolver::solvePointAlone(int j, double s, double b) const
{
    return method_ == ContactMethod::quadraticSpline && !contacts_[j].law.bilateral
               ? splines_[size_t(j)].solve(s, b, system_.coupling()(j, j))
               : system_.solveAlone(j, s, b);
}

void ModalSolver::finishOnMovingBridge()
{
    if (pairedOnBridge_)
    {
        finishPairStep();
        return;
    }
    if (!pressing_.empty())
        applyContactForces();
    endSingleStep();
}

bool ModalSolver::isLoneSpring(int most) const
{
    return loneSpring() && state_.pairable() && externalForce_ == 0.0 && transform_ == nullptr
           && state_.activeCount() <= most;
}

ModalSolver::LoneSpring ModalSolver::takeLoneSpring()
{
    state_.toSingle();
    const ContactLaw& law = contacts_[0].law;
    LoneSpring out;
    out.modes = state_.activeCount();
    out.a = state_.a();
    out.e = state_.e();
    out.phi = state_.phi(0);
    out.q = state_.q();
    out.qPrev = state_.qPrev();
    out.height = contacts_[0].height;
    out.stiffness = law.stiffness;
    out.chordSlope = chordSlope(law, 0.0, 0.0).derivative;  // the spring's G' at every r
    out.weight = contacts_[0].weight;
    out.coupling = system_.coupling()(0, 0);
    out.stringCoupling = stringCoupling_(0, 0);
    out.forceScale = forceScale_;
    out.uC = uC_[0];
    out.uCPrev = uCPrev_[0];
    out.slope = slope_[0];
    out.kappa = compliance_.kappa();
    out.pushPerSlope = compliance_.pushPerSlope(0);
    out.forcePerSlope = compliance_.forcePerSlope(0);
    const ResidualCompliance::PointState spring = compliance_.pointState(0);
    out.delta = spring.delta;
    out.deltaPrev = spring.deltaPrev;
    out.springForce = spring.force;
    out.springForcePrev = spring.forcePrev;
    return out;
}

void ModalSolver::giveLoneSpring(const double* q, const double* qPrev, const LoneSpring& state)
{
    state_.restartSingle();
    for (int i = 0; i < state.modes; ++i)
        state_.set(i, q[i], qPrev[i]);
    uC_[0] = state.uC;
    uCPrev_[0] = state.uCPrev;
    slope_[0] = state.slope;
    compliance_.setPointState(0, {state.delta, state.deltaPrev, state.springForce, state.springForcePrev});
    lastPenetration_ = -std::numeric_limits<double>::infinity();
    trialBefore_ = trialMove_ = std::numeric_limits<double>::quiet_NaN();
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

double ModalSolver::energyOnBridge(double now, double before) const
{
    return stringEnergy() + contactPotentialEnergy(uC_.data(), uCPrev_.data(), true, now, before)
           + compliance_.energy();
}

void ModalSolver::refreshReachOnBridge(double H, double rise)
{
    reach_.refresh(
        H, contacts_, [this](int j) { projectPoint(j); }, [this](int j) { slope_[size_t(j)] = 0.0; }, rise);
    // A point left out presses no more: the next trial (trialOnMovingBridge) poses none of them.
    std::erase_if(pressing_, [this](int j) { return !reach_.live(j); });
}

void ModalSolver::wakeAllMidStep()
{
    if (!pairedOnBridge_)
        reach_.wakeAll([this](int j) { projectPointMidStep(j); });
    trialBefore_ = trialMove_ = std::numeric_limits<double>::quiet_NaN();  // a trial without them is no solve
}

// Point j joins after the prediction was written over q^{n-1} (the single layout, no explicit force:
// a pushed string has every point live): u^n from q^n, u~ from q~, and u^{n-1} from
// q^{n-1} = (a q^n - q~) / e, mode by mode, exact to rounding where e >= 1e-2; the steeply damped
// modes after (ModalState::steepFrom) from their q^{n-1} kept by the prediction.
void ModalSolver::projectPointMidStep(int j)
{
    const double* q = state_.q();
    const double* predicted = state_.qPrev();
    const double* a = state_.a();
    const double* e = state_.e();
    const double* phi = state_.phi(j);
    const int steep = state_.steepFrom();
    double u = 0.0, uPrev = 0.0, uNext = 0.0;
    for (int p = 0; p < state_.activeCount(); ++p)
    {
        u += phi[p] * q[p];
        uNext += phi[p] * predicted[p];
        uPrev += phi[p] * (p < steep ? (a[p] * q[p] - predicted[p]) / e[p] : steepPrevious_[size_t(p - steep)]);
    }
    uC_[size_t(j)] = u;
    uCPrev_[size_t(j)] = uPrev;
    uTilde_[size_t(j)] = uNext;
}

// sum_j w_j (psi_j(u^n) + psi_j(u^{n-1})) / 2 for the points' displacements u at n and n-1 (with
// `liveOnly`, over the live points a split step keeps: the others are off their obstacle, and their u
// is not kept).
double ModalSolver::contactPotentialEnergy(const double* u, const double* uPrev, bool liveOnly, double raise,
                                           double raiseBefore) const
{
    auto psi = [&](int j, double penetration) {
        return method_ == ContactMethod::quadraticSpline && !contacts_[j].law.bilateral
                   ? splines_[size_t(j)].potential(penetration)
                                                         : contactPotential(contacts_[j].law, penetration);
    };
    double sum = 0.0;
    for (int j = 0; j < P_; ++j)
        if (!liveOnly || (reach_.live(j) && engaged_.engaged(j)))
            sum += contacts_[j].weight * 0.5
               * (psi(j, contacts_[j].height + raise - u[j] - compliance_.delta(j))
                  + psi(j, contacts_[j].height + raiseBefore - uPrev[j] - compliance_.deltaPrev(j)));
    return sum;
}

double ModalSolver::pickupCompliance(bool second) const
{
    return pickups_[second ? 1 : 0].compliance(mu_, omega_);
}

double ModalSolver::pickupForceBound(double energy, bool second) const
{
    const auto& pickup = pickups_[second ? 1 : 0];
    double sum = 0.0;
    for (int j = 0; j < P_; ++j)
        if (const double response = pickup.responseAt(j); response != 0.0)
            sum += std::abs(response)
                   * largestForceDensity(contacts_[size_t(j)].law, contacts_[size_t(j)].weight, 2.0 * energy);
    return sum;
}

double ModalSolver::pickupAboveBand(bool second) const
{
    return pickups_[second ? 1 : 0].aboveBand(state_);
}

void ModalSolver::retune(const double* omega, const double* sigma, double complianceScale, double pickupScale,
                         RetuneMotion motion)
{
    state_.toSingle();  // the paired layout's corrections were made with the old coefficients
    const bool moved = motion == RetuneMotion::keepActions && keepModeActions(omega, sigma);
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
    if (!modeScale_.empty())
        followStaticGains();
    for (auto& pickup : pickups_)
        pickup.setWeights(omega_, pickupScale);
    state_.fillTables(coeffs_, coeffsReleased_, pickups_[0].weights(), pickups_[1].weights());
    for (int k = 0; k < 2; ++k)
        if (const double* h = activePickupWeights(k))
            pickups_[size_t(k)].rereadActive(h, state_, pickupForces(), !transform_);
    if (compliance_.active())
        compliance_.rescale(complianceScale, contacts_);
    if (compliance_.active() || !modeScale_.empty())
        updateCouplings();
    if (moved)
    {
        // The contact points' displacements at n and n-1, read from the modes moved (on the rows as
        // the static-exact forcing left them), and what the quadratised contact keeps of them.
        projectActive(state_.q(), uC_.data());
        projectActive(state_.qPrev(), uCPrev_.data());
        if (method_ == ContactMethod::quadratised)
            quadratised_.restart(contacts_, uC_.data(), uCPrev_.data());
        trialBefore_ = trialMove_ = std::numeric_limits<double>::quiet_NaN();
    }
    measureReach();
    reach_.markStale();  // the same motion at another pitch holds another energy
}

// A string retuned while it sounds keeps each mode's action E/omega (the adiabatic invariant of an
// oscillator whose frequency moves) at its phase, so that a pitch moving back and forth, however
// fast, returns the string to the energy it had: kept state, a retune in one phase of the motion
// adds energy and in another takes it, and retunes at the chunk rate pump a mode parametrically.
// Mode i at (x, y) = (q^n, q^{n-1}) under q^{n+1} = a q^n - e q^{n-1}, a = 2R cos(theta), e = R^2
// (R = exp(-sigma dt), theta = w_d dt), is A R^n (cos psi, cos(psi - theta) / R): its phase's sine
// part S = A R^n sin psi = (R y - x cos theta) / sin theta. At the new (R', theta') the same phase
// has y' = (x cos theta' + S sin theta') / R', and (x, y') is scaled by s so that its discrete
// energy E(x, y) = ((1+e)/2)(x^2 + y^2) - a x y (times mu / 2dt^2) is omega'/omega times the old.
// The map is homogeneous, so it holds in the static-exact forcing's coordinates p = q / sqrt(gamma)
// too, whose energy is the scheme's (the mode of mass mu / gamma): s takes the gain's change as well,
// which followStaticGains then divides out. A mode whose
// frequency stays (a new damping alone), one damped past a tenth of its motion in a step, critically
// or beyond, or within 0.14 of the step's Nyquist phase keeps its state. Returns whether any moved.
bool ModalSolver::keepModeActions(const double* omega, const double* sigma)
{
    const double extra = state_.released() ? releaseSigma_ : 0.0;
    double* q = state_.q();
    double* qPrev = state_.qPrev();
    bool moved = false;
    for (int i = 0; i < state_.activeCount(); ++i)
    {
        const int p = state_.activeMode(i);
        const double wOld = omega_[p], wNew = omega[p];
        const double sOld = sigma_[p] + extra, sNew = sigma[p] + extra;
        if (wNew == wOld || !(sOld < wOld) || !(sNew < wNew))
            continue;
        const double tOld = std::sqrt(wOld * wOld - sOld * sOld) * dt_, tNew = std::sqrt(wNew * wNew - sNew * sNew) * dt_;
        const double rOld = std::exp(-sOld * dt_), rNew = std::exp(-sNew * dt_);
        if (tOld > 3.0 || tNew > 3.0 || rOld < 0.1 || rNew < 0.1)
            continue;
        const double x = q[i], y = qPrev[i];
        const double S = (rOld * y - x * std::cos(tOld)) / std::sin(tOld);
        const double yNew = (x * std::cos(tNew) + S * std::sin(tNew)) / rNew;
        auto energy = [](double r, double t, double u, double v) {
            return 0.5 * (1.0 + r * r) * (u * u + v * v) - 2.0 * r * std::cos(t) * u * v;
        };
        const double before = energy(rOld, tOld, x, y), after = energy(rNew, tNew, x, yNew);
        if (!(before > 0.0 && after > 0.0))
            continue;
        // The static-exact forcing's gains follow (followStaticGains divides p by g'/g): its energy,
        // that of p, is kept through them.
        const double gains = modeScale_.empty() ? 1.0
                                                : std::sqrt(staticForcingGain(wNew, sigma[p], dt_)) / modeScale_[size_t(p)];
        const double scale = gains * std::sqrt(wNew / wOld * before / after);
        q[i] = scale * x;
        qPrev[i] = scale * yNew;
        moved = true;
    }
    return moved;
}

// Each mode's new sqrt(gamma_p) over its old, r_p, divides its coordinate p_p and multiplies its
// contact shapes, excitation and pickup weights: q_p = sqrt(gamma_p) p_p and every reading stay the
// same motion. The string's coupling A = (dt^2/mu) Phi Phi^T W is formed again from the new shapes
// (P^2 M products: a few tens of thousands on a voice).
void ModalSolver::followStaticGains()
{
    for (int p = 0; p < M_; ++p)
    {
        const double g = std::sqrt(staticForcingGain(omega_[p], sigma_[p], dt_));
        gainRatio_[size_t(p)] = g / modeScale_[size_t(p)];
        modeScale_[size_t(p)] = g;
    }
    state_.rescaleModes(gainRatio_.data());
    auto& shapes = shapes_.edit();
    for (int j = 0; j < P_ && !shapes.empty(); ++j)
        scaleByModes(shapes.data() + size_t(j) * M_, M_, gainRatio_);
    if (!excitationShape_.empty())
        scaleByModes(excitationShape_.edit().data(), M_, gainRatio_);
    for (auto& pickup : pickups_)
        pickup.scaleConfigured(gainRatio_.data());
    fillStringResponse(stringCoupling_);
}

void ModalSolver::updateCouplings()
{
    const bool withCompliance = compliance_.active();
    for (int i = 0; i < P_; ++i)
        for (int j = 0; j < P_; ++j)
        {
            const double a = stringCoupling_(i, j) + (withCompliance ? compliance_.coupling()(i, j) : 0.0);
            pointCoupling_(i, j) = a / contacts_[j].weight;
            couplingScratch_(i, j) = a;
        }
    system_.setCoupling(couplingScratch_);
    trialBefore_ = trialMove_ = std::numeric_limits<double>::quiet_NaN();  // a trial of the old coupling
}

void ModalSolver::setContact(int j, const ContactLaw& law, double height)
{
    const bool lawChanged = contacts_[size_t(j)].law.stiffness != law.stiffness
                            || contacts_[size_t(j)].law.exponent != law.exponent
                            || contacts_[size_t(j)].law.bilateral != law.bilateral;
    if (contacts_[size_t(j)].height != height)
        wakeAll();  // a sleeping point may now be within reach
    reach_.markStale();  // and the obstacles' energy is another
    contacts_[size_t(j)].law = solverLaw(law, dt_);
    contacts_[size_t(j)].height = height;
    system_.setLaw(j, contacts_[size_t(j)].law);
    trialBefore_ = trialMove_ = std::numeric_limits<double>::quiet_NaN();  // a trial of the old law
    findSpringPoint();
    if (method_ == ContactMethod::quadraticSpline && lawChanged && !law.bilateral)
        splines_[size_t(j)].setLaw(law);
}

// springPoint_: the one bilateral point of a string solved by the energy-conserving method with
// coupled points, else -1; springsUntried_: a string of several points with springs that is not that.
void ModalSolver::findSpringPoint()
{
    springPoint_ = -1;
    int springs = 0;
    for (int j = 0; j < P_; ++j)
        if (contacts_[size_t(j)].law.bilateral)
        {
            springPoint_ = j;
            ++springs;
        }
    // A diagonal system (the reference grid) is solved point by point, not by the Schur complement.
    if (springs != 1 || method_ != ContactMethod::energyConserving || system_.isDiagonal())
        springPoint_ = -1;
    springsUntried_ = P_ > 1 && springs > 0 && springPoint_ < 0;
}

void ModalSolver::displacementAt(const double* shapes, int count, double* out)
{
    state_.toSingle();
    const double* q = state_.q();
    for (int k = 0; k < count; ++k)
    {
        double u = 0.0;
        for (int i = 0; i < state_.activeCount(); ++i)
        {
            const int p = state_.activeMode(i);
            u += toModeCoordinate(p, q[i]) * shapes[size_t(k) * M_ + p];
        }
        out[k] = u;
    }
}

int ModalSolver::solveContacts()
{
    if (method_ == ContactMethod::energyConserving)
        return system_.solve(s_.data(), b_.data(), r_.data(), slope_.data(), stepRows(), stepCount());
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
        kernels::pairStep(state_.a(), state_.e(), state_.qPrev(), state_.q(), state_.settled(), state_.h(), state_.h2(),
                          state_.singlePhi(), state_.c1(), state_.c2(), state_.steppedCount(), state_.pickupCount(),
                          state_.padded(), pass_);
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
        lastPenetration_ = contacts_[0].law.bilateral ? -std::numeric_limits<double>::infinity()
                                                      : contacts_[0].height - uC_[0] - compliance_.delta(0);
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
        const auto sol = solvePointAlone(j, s_[j], b_[j]);
        r_[j] = sol.r;
        slope_[j] = sol.slope;
        most = std::max(most, sol.iterations);
    }
    return most;
}

void ModalSolver::stepSingle()
{
    system_.beginStep();
    if (reach_.enabled())
    {
        if (externalForce_ != 0.0)
            wakeAll();
        else if (reach_.checkDue())
            refreshReach();
    }
    splitStep_ = engaged_.splits(state_.activeCount()) && externalForce_ == 0.0;
    if (!splitStep_ && engaged_.anyOut())
        engageEveryPoint();
    if (splitStep_)  // a point engaged mid-step takes their q^{n-1} from here (projectPointMidStep)
        keepSteepPrevious();
    predictAtPoints();
    lastIterations_ = 0;
    pressing_.clear();
    if (P_ > 0)
    {
        for (int k = 0; k < stepCount(); ++k)
            poseContactEquation(stepRows()[k]);
        lastIterations_ = solveContacts();
        while (splitStep_ && engageReached())
        {
            ++engaged_.counters.resolves;
            lastIterations_ += solveContacts();
        }
        for (int k = 0; k < stepCount(); ++k)
            if (slope_[stepRows()[k]] != 0.0)
                pressing_.push_back(stepRows()[k]);
    }
    if (!pressing_.empty())
        applyContactForces();
    endSingleStep();
    if (splitStep_)
    {
        ++engaged_.counters.steps;
        engaged_.counters.engaged += engaged_.count();
    }
    splitStep_ = false;
}

void ModalSolver::poseContactEquation(int j)
{
    s_[j] = contacts_[j].height - uCPrev_[j] - compliance_.deltaPrev(j);
    b_[j] = uTilde_[j] - uCPrev_[j] - compliance_.restoring(j);
}

void ModalSolver::keepSteepPrevious()
{
    std::copy(state_.qPrev() + state_.steepFrom(), state_.qPrev() + state_.activeCount(), steepPrevious_.begin());
}

void ModalSolver::measureReach()
{
    reach_.measure(coeffs_, coeffsReleased_, shapes_, dt_, mu_, compliance_, contacts_);
    measureTail();
}

// H^{n-1/2} measured: a point that joins gets its u^n and u^{n-1}; one left out, no force.
void ModalSolver::refreshReach()
{
    const double H = stringEnergy() + obstacleEnergy() + compliance_.energy();
    reach_.refresh(
        H, contacts_,
        [this](int j) {
            projectPoint(j);
            engaged_.engage(j);
        },
        [this](int j) {
            slope_[size_t(j)] = 0.0;
            engaged_.engage(j);  // out of reach: not the split's to keep
        });
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
    const int fused = transform_ || externalForce_ != 0.0 || splitStep_ ? 0 : std::min(live, kernels::kMaxFused);
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
    if (splitStep_)
    {
        predictSplit();
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
    const int* rows = stepRows();
    for (int k = 0; k < stepCount(); ++k)
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
    const int* rows = stepRows();
    for (int k = 0; k < stepCount(); ++k)
    {
        const int j = rows[k];
        const double u = uTilde_[j];
        uCPrev_[j] = uC_[j];
        uC_[j] = u;
        if (!contacts_[j].law.bilateral)  // a spring-damper's stretch is no penetration
            deepest = std::max(deepest, contacts_[j].height - u - compliance_.delta(j));
    }
    lastPenetration_ = deepest;
    state_.swapSingle();
    for (auto& pickup : pickups_)
        pickup.value = pickup.predicted;
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

double ModalSolver::damperLoss() const
{
    if (method_ == ContactMethod::penalty || method_ == ContactMethod::quadratised)
        return 0.0;
    double sum = 0.0;
    for (int j = 0; j < P_; ++j)
        if (contacts_[j].law.bilateral)
            sum += contacts_[j].weight * contacts_[j].law.stepDamping * r_[j] * r_[j];
    return 0.5 * sum;  // H^{n+1/2} - H^{n-1/2} takes half the work f r over the two-step r
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
