// The solver's step, in its two forms (one pass per step; two steps per pass with one point), its
// force and its energy. Construction and state set-up: ModalSolverSetup.cpp; on a moving bridge:
// ModalSolverBridge.cpp; retunes and contact laws: ModalSolverRetune.cpp.
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
