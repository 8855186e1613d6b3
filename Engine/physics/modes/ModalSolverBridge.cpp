// The string on a moving bridge (a body's: SharedBody.h): its step split around the bridge's solve, the
// trials and force slopes the body's secant takes, and a lone spring handed to a bank and back.
#include "physics/modes/ModalSolver.h"

#include "physics/modes/ModalKernels.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace jawari
{

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

}  // namespace jawari
