#pragma once
// The mixed modal scheme of docs/design.md section 2: M modes, each advanced by its exact update, and
// the energy-conserving contact force at P contact points.
//
//   q~ = a q^n - e q^{n-1}                      (contact-free prediction, exact per mode)
//   r + (dt^2/mu) Phi Phi^T W G(r) = Phi q~ - u_C^{n-1}     (implicit contact, ContactSystem)
//   q^{n+1} = q~ + (dt^2/mu) Phi^T W f,   f = -G(r)
//
// Two ways to reach the contact points:
//  - projection: Phi stored (P x M), O(M P) per step; any points, any M (the few-point path);
//  - a GridTransform: the reference grid (M = N - 1, every contact point on a distinct node
//    x_i = i L/N), where Phi Phi^T W is diagonal and q <-> u is a DST-I, O(N log N) per step.
//
// The parts, each in its own file: the active modes and their stepping arrays (ModalState), the
// contact methods (ContactSystem: the energy-conserving Newton; QuadratisedContact;
// PenaltyContact), the residual compliance (ResidualCompliance), the transform (GridTransform), the
// pickups' readings (PickupReadout, one per pickup) and the points within the string's reach
// (ContactReach).

#include "physics/contact/ContactMethod.h"
#include "physics/contact/ContactReach.h"
#include "physics/contact/ContactSpline.h"
#include "physics/contact/ContactSystem.h"
#include "physics/contact/EngagedPoints.h"
#include "physics/modes/ExactOscillator.h"
#include "physics/string/GridTransform.h"
#include "physics/modes/ModalKernels.h"
#include "physics/modes/ModalState.h"
#include "physics/contact/Obstacle.h"
#include "physics/contact/PenaltyContact.h"
#include "physics/modes/PickupReadout.h"
#include "physics/contact/QuadratisedContact.h"
#include "physics/modes/ResidualCompliance.h"
#include "physics/modes/StampedVector.h"
#include "physics/string/StringModel.h"

#include <array>
#include <memory>
#include <optional>
#include <limits>
#include <vector>

namespace jawari
{

struct ModalSolverConfig
{
    double lengthMetres = 1.002;
    double linearDensity = 1.17e-3;
    double timeStep = 5e-7;  // s
    ModalTable modes;
    std::vector<ContactPoint> contacts;
    // phi_p(x_j) of every contact point and mode (P x M, row-major), when the modes are not one
    // polarisation's sine modes (both polarisations of a string as one set: Polarisations.h).
    // Empty: the string's modes, phi_p(x_j) = sqrt(2/L) sin(p pi x_j / L). Projection path only.
    std::vector<double> contactShapes;
    std::vector<double> pickupWeights;  // h_p: the pickup reads sum_p h_p q_p
    std::vector<double> secondPickupWeights;  // a second pickup's (the right channel's); empty for none
    // The pickups read the modes up to this frequency (Hz) as they move, and the modes from 1.25
    // times it by their static response to the contact and excitation forces: their ringing is above
    // what the voice's decimator passes (it stops from the host's Nyquist frequency). Between the two,
    // a share of each, linear in its frequency (a pitch bend carries a mode across without a step).
    // 0: every mode as it moves.
    double pickupBandHz = 0.0;
    // The reference grid's transform to the contact points; empty: projection.
    GridTransformFactory transform;
    // Where setExternalForce() pushes (the voice's pluck); its modes are kept active.
    std::optional<double> excitationPosition;
    // The force's shape over the modes (M values) when not the sine modes' phi_p(excitationPosition).
    std::vector<double> excitationShape;
    // How a shape of the string, given in one polarisation's sine modes (m values: a pluck), sits in
    // these modes: M x m row-major, q = B q_shape (both polarisations: Polarisations.h). Empty: the
    // modes are the sine modes (m = M, B = I). The solver does not use it; the voice plucks with it.
    std::vector<double> shapeToModes;
    // Extra damping (1/s, every mode) of the second coefficient set, selected by setReleased().
    double releaseSigma = 0.0;
    // Residual compliance (ResidualCompliance.h), P x P row-major, m/N: C_ij = sum over the dropped
    // modes of phi_p(x_i) phi_p(x_j) / (mu w_p^2). Projection path only; empty for none.
    std::vector<double> contactCompliance;
    // The share theta in [0, 1] of the residual compliance's two-step change that it dissipates
    // (ResidualCompliance.h): 0 conserves its energy, 1 is backward Euler on the massless spring.
    double complianceLoss = 1.0;
    ContactMethod method = ContactMethod::energyConserving;
    // Step every mode, even those nothing couples to and that start at rest: the plugin's voices
    // take state across rebuilds (a new pluck or pickup point) and must not drop a ringing mode.
    bool keepEveryMode = false;
    // Leave the contact points the string cannot reach out of the step (ContactReach);
    // off: every point projected and solved every step (the same motion to rounding, at more cost).
    bool leaveOutOfReach = true;
    // Of those, project in full and solve only the points that the high modes may carry to their
    // obstacle, on a step over many modes (EngagedPoints); off: every live point (the same motion, a
    // comparison).
    bool splitModes = true;
    // Each mode answers a force with gamma_p = C2_p / omega_p^2 of the paper's gain dt^2/mu
    // (staticForcingGain), so that a force held still deflects it by exactly its static compliance:
    // the paper's scheme gives every mode dt^2/mu a step, far more than a mode with omega dt or
    // sigma dt >> 1 can move (docs/design.md section 2, "The forcing of the fast modes"). The free
    // motion stays exact and the energy balance exact. Built as the same scheme in coordinates
    // p_p = q_p / sqrt(gamma_p): the contact shapes, pickups and excitation scaled by sqrt(gamma_p).
    // Projection path only. A retune forms the gains again and carries the motion over.
    bool staticExactForcing = false;
};

class ModalSolver
{
public:
    explicit ModalSolver(const ModalSolverConfig& config);  // OFF: tables, Phi, the transform
    ModalSolver(const ModalSolver&) = delete;
    // RT: this solver becomes the other's exact copy, its state and every table (solvers on the grid
    // transform excepted: OwnedGridTransform). Only into a solver built from the same configuration,
    // whose arrays have the same sizes and reserved capacities: then nothing is allocated (the
    // instrument's backups for a second core: StringWorker).
    ModalSolver& operator=(const ModalSolver&) = default;

    // OFF/CT: modal displacements at t = 0 with zero velocity; q^{-1} is set from each mode's
    // exact free motion, so without contact the run is the analytic solution (modes damped by
    // more than e^0.5 per step start with q^{-1} = q(+dt) instead, see the .cpp).
    void setInitialDisplacement(const std::vector<double>& modalDisplacement);
    // OFF/CT: an explicit state pair (q^n, q^{n-1}), in the solver's coordinates (p_p with
    // staticExactForcing, as modalState() gives them).
    void setState(const std::vector<double>& current, const std::vector<double>& previous);

    void step();  // RT: n -> n+1
    // RT: step() split around its contact solve, for a caller that solves many strings' points
    // together (StringBank). beginStep() takes the whole step and returns false unless the step has
    // exactly one energy-conserving contact point on the paired path (no explicit force); then it
    // has predicted the step, `request` holds the point's scalar equation, and finishStep() takes
    // its solution and completes the step.
    bool beginStep(ScalarContactRequest& request);
    // RT: whether the next step runs a pass over the modes, and the cache asked for its arrays.
    bool nextStepPasses() const { return !state_.pairable() || state_.layout() != ModalState::Layout::pairMiddle; }
    void prefetchPass() const { state_.prefetchPass(); }
    void finishStep(const ScalarContactSolution& solution);
    // RT: step() in three parts around a bridge that moves (SharedBody): predictOnMovingBridge()
    // predicts the step (one pass over the modes); solveOnMovingBridge(before, move), as many times as
    // the caller needs, solves the contact with every obstacle raised by the bridge's displacement,
    // `before` at n-1 and `before + move` at n+1, and returns sum_j w_j G_j (the points' forces on the
    // bridge, N, < 0 while they press it down); finishOnMovingBridge() completes the step with the last
    // solve. The energy-conserving method or the quadratic spline. The points out of reach are the
    // caller's to choose (refreshReachOnBridge(), wakeAllPoints()): the string's own energy no longer
    // bounds its motion, the joined one does.
    void predictOnMovingBridge();
    double solveOnMovingBridge(double before, double move);
    void finishOnMovingBridge();
    // RT, between predictOnMovingBridge() and the step's first solveOnMovingBridge(): what that solve
    // would return if the point that pressed alone at the last step presses alone again (its scalar
    // equation, the others off): a trial for the caller's iteration. Nothing is solved; only the
    // trial's own solution is kept, which the solve at the same bridge takes where it poses the same
    // equation (ContactSystem::solveAlone). 0 if no point pressed; NaN if two did (then only a solve
    // tells). A string with one point: its scalar equation, which is its solve, whatever it did
    // before. A string held by one spring (a bilateral point, energy-conserving method, coupled
    // points): the spring with its one presser, or alone (trialWithSpring); with two points that is
    // the root its solve finds, and the solve at the same bridge keeps it. NaN for a string with
    // points and springs that no trial poses (two springs, or a spring solved point by point).
    // `slope` (optional): the trial's dF/dmove (chordSlopeDerivative).
    double trialOnMovingBridge(double before, double move, double* slope = nullptr) const;
    // RT, after solveOnMovingBridge: dF/dmove at its solution with the same points pressing (the
    // implicit function's: r + A G(r) = b with b falling by one per metre the bridge moves), for the
    // caller's Newton step. NaN where G' has no closed form (the quadratic spline's several points)
    // or more than kMostSlopePoints press.
    double solvedForceSlope() const;
    static constexpr int kMostSlopePoints = 8;
    // A string held by one spring and nothing else (a sympathetic string on its bridge), handed to a
    // caller that steps it elsewhere (LinearStringBank) and back. Its step, single form, is
    //   q~ = a q^n - e q^{n-1},  u~ = phi . q~,
    //   s = h + before - u_C^{n-1} - delta^{n-1},  b = u~ - u_C^{n-1} - kappa delta^{n-1} - move,
    //   G = -K s + d r with r = (b + k K s) / (1 + k d)   (d = K/2 + R/(2 dt): the spring's chord slope),
    //   u_C^{n+1} = u~ - kString G,  q^{n+1} = q~ - (dt^2/mu) w G phi,  and the residual compliance's
    // advance (ResidualCompliance::PointState), its force on the bridge w G.
    struct LoneSpring
    {
        int modes = 0;  // active modes: a, e, phi, q and qPrev hold this many
        const double* a = nullptr;
        const double* e = nullptr;
        const double* phi = nullptr;
        const double* q = nullptr;      // q^n
        const double* qPrev = nullptr;  // q^{n-1}
        // Constants.
        double height = 0.0, stiffness = 0.0, chordSlope = 0.0, weight = 0.0;
        double coupling = 0.0, stringCoupling = 0.0, forceScale = 0.0;
        double kappa = 1.0, pushPerSlope = 0.0, forcePerSlope = 0.0;
        // State: u_C at n and n-1, the last step's G, the spring's delta and g at n and n-1.
        double uC = 0.0, uCPrev = 0.0, slope = 0.0;
        double delta = 0.0, deltaPrev = 0.0, springForce = 0.0, springForcePrev = 0.0;
    };
    // Whether the string is one (loneSpring) that takes two steps per pass, with no force on it and
    // at most `most` active modes.
    bool isLoneSpring(int most) const;
    // RT: its tables and state, the state rewritten in the single layout first (the same motion).
    LoneSpring takeLoneSpring();
    // RT: its state after steps taken elsewhere: q^n, q^{n-1} (`modes` values each), u_C, the spring's
    // and the last step's slope; the string goes on from there as if it had taken them itself.
    void giveLoneSpring(const double* q, const double* qPrev, const LoneSpring& state);

    // RT, on a moving bridge, before predictOnMovingBridge(): the live points for a string whose
    // energy stays at most H while its bridge rises by at most `rise` (m; ContactReach::refresh), or
    // every point live. wakeAllMidStep(): every point live from now, between
    // predictOnMovingBridge() and finishOnMovingBridge(), so that the step's next solve takes them
    // (SharedBody, when a step ran beyond what the live points were chosen for). Without the reach
    // (leavesOutOfReach()) every point stays live.
    void refreshReachOnBridge(double H, double rise);
    void wakeAllPoints() { wakeAll(); }
    void wakeAllMidStep();
    // RT: whether H may have risen since the reach was last refreshed (a retune, a release, a new
    // state, a force that ended), and whether a force pushes the string now.
    bool reachStale() const { return reach_.stale(); }
    bool pushed() const { return externalForce_ != 0.0; }
    // RT: H^{n-1/2} with every obstacle raised by the bridge's `now` at n and `before` at n-1: the
    // string's, its obstacles' and the residual compliance's. No allocation.
    double energyOnBridge(double now, double before) const;

    // RT: a point force (N) at the excitation position, applied explicitly from the next step on
    // (part of the prediction: q~ += (dt^2/mu) F phi_e) until set back to 0.
    void setExternalForce(double newtons);
    // RT: switch to the damping set with releaseSigma added (note-off) or back. The state carries
    // over unchanged, so the sound does not jump.
    void setReleased(bool released)
    {
        state_.useReleased(released);
        reach_.markStale();  // the energy is measured with the other coefficient set from now on
    }
    bool released() const { return state_.released(); }
    // RT: the string part of H^{n-1/2} (no contact part), without allocating.
    double stringEnergy() const;
    // RT: the obstacles' part of H^{n-1/2} from the solver's own contact displacements (the
    // quadratised energy for that method), without allocating; the residual compliance's spring
    // is left out (energy() has it).
    double obstacleEnergy() const;
    // OFF: sum_p h_p^2 / (mu w_p^2): |pickup| <= sqrt(2 H this) for a string of energy H (of the
    // second pickup with `second`).
    double pickupCompliance(bool second = false) const;
    // RT: the most the contact forces can add to a pickup's reading at once for a string whose H
    // stays at most `energy`: sum_j |its response to point j's force| times the largest force H
    // allows there (at n+1 and n-1 each point's potential is at most 2 H). It bounds the static
    // reading of the modes above the pickup's band, which sqrt(2 H G) does not.
    double pickupForceBound(double energy, bool second = false) const;
    // RT: what the pickup does not read of the modes above its band as they are now (their static
    // share of h_p q_p): a held shape's part that the first sample leaves out.
    double pickupAboveBand(bool second = false) const;

    // How a retune carries a sounding string's motion: its state (q^n, q^{n-1}) as it is (a string
    // just given new coefficients, its motion already at them), or each mode's action, its energy over
    // its frequency, at its phase (a string whose tension moves while it sounds: keepModeActions).
    enum class RetuneMotion
    {
        keepState,
        keepActions
    };
    // RT: new frequencies and damping for every mode (omega, sigma: M values each, rad/s and 1/s),
    // the residual compliance scaled by `complianceScale` from the configured one (1/r^2 when every
    // frequency is scaled by r) and the pickup weights by `pickupScale`, the motion carried as
    // `motion` says. No allocation.
    void retune(const double* omega, const double* sigma, double complianceScale, double pickupScale = 1.0,
                RetuneMotion motion = RetuneMotion::keepState);
    // RT: the law and height of contact point j (the obstacle's automation). No allocation (the
    // quadratic-spline method rebuilds its knots within their reserved capacity: ContactSpline).
    void setContact(int j, const ContactLaw& law, double height);
    const ContactPoint& contact(int j) const { return contacts_[size_t(j)]; }
    const std::vector<double>& omega() const { return omega_; }
    const std::vector<double>& sigma() const { return sigma_; }
    // RT: u(x_k) = sum_p q_p^n shapes[k M + p] for `count` points, with shapes[k M + p] = phi_p(x_k)
    // tabulated by the caller (the editor's drawing of the string). No allocation.
    void displacementAt(const double* shapes, int count, double* out);

    // RT: the string released from rest at the given modal displacement (M values), q^{-1} from
    // each mode's exact free motion as in setInitialDisplacement(). Only the active modes take it
    // (all of them with keepEveryMode). No allocation.
    void startFrom(const double* modalDisplacement);

    // RT: the string at rest at zero (after a blow-up), without touching the tables.
    void resetToRest();
    // RT: take the string state of another solver of the same modes (a new obstacle or contact
    // model handed over from the control thread). No allocation.
    void takeMotionFrom(ModalSolver& other);

    int modeCount() const { return M_; }
    // sqrt(gamma_p) of every mode with staticExactForcing (q_p = sqrt(gamma_p) p_p), else empty.
    const std::vector<double>& modeScale() const { return modeScale_; }
    // Modes actually stepped: a mode that no contact point couples to (phi_p(x_j) = 0 for every j,
    // to 1e-13 of the largest) and that starts at zero (to 1e-13 of the largest mode) stays at
    // zero, so it is skipped (the centre obstacle and centre pluck leave every even mode out).
    // Projection path only.
    int activeModeCount() const { return state_.activeCount(); }
    int contactCount() const { return P_; }
    ContactMethod contactMethod() const { return method_; }
    bool leavesOutOfReach() const { return reach_.enabled(); }
    // Points the contact solve takes this step: those within the string's reach (ContactReach).
    int livePointCount() const { return reach_.liveCount(); }
    // Over the run: the split steps (EngagedPoints) and what they solved.
    const EngagedPoints::Counters& splitCounters() const { return engaged_.counters; }
    bool pointLive(int j) const { return reach_.live(j); }
    // Whether the last step solved point j: live, and engaged on a split step (EngagedPoints).
    bool pointSolved(int j) const { return reach_.live(j) && engaged_.engaged(j); }
    bool usesTransform() const { return transform_ != nullptr; }
    double timeStep() const { return dt_; }
    double linearDensity() const { return mu_; }

    double pickup() const { return pickups_[0].value; }              // RT: sum h_p q_p^n
    double secondPickup() const { return pickups_[1].value; }        // RT: the second pickup's, 0 without one
    int lastIterations() const { return lastIterations_; }          // RT: contact solve of the last step
    // RT: whether the last solveOnMovingBridge took the step's last trial as its solve (no solve of its own).
    bool lastSolveWasTrial() const { return lastSolveWasTrial_; }
    // RT: the force (N) the last step's contact put on the string at point j, -w_j G_j (> 0 pushes it up).
    double contactForce(int j) const { return -contacts_[size_t(j)].weight * slope_[size_t(j)]; }
    // RT: max_j g_j - u_j^n (m) over the unilateral points
    double lastMaxPenetration() const { return lastPenetration_; }

    // OFF: the full modal state, q^n (previous = false) or q^{n-1}, in the solver's coordinates
    // (p_p = q_p / sqrt(gamma_p) with staticExactForcing: modeScale()).
    std::vector<double> modalState(bool previous = false);

    // H^{n-1/2} of docs/design.md section 2 from the stored (q^n, q^{n-1}), contact part
    // recomputed from the modal state (not from the solver's bookkeeping). CT/OFF.
    struct Energy
    {
        double total = 0.0;
        double contact = 0.0;  // sum_j w_j (psi_j(u^n) + psi_j(u^{n-1})) / 2
    };
    Energy energy();
    // The losses of a step for full states (q^{n+1}, q^{n-1}):
    //   H^{n+1/2} - H^{n-1/2} = -sum mu (1-e_p) ((q^{n+1}-q^{n-1})/(2dt))^2.
    double stepLoss(const double* next, const double* previous) const;
    // RT: what the bilateral points' dampers took in the last step (J), sum_j w_j (R_j / 2dt) r_j^2 / 2
    // with r_j = u_j^{n+1} - u_j^{n-1}: the rest of the balance. 0 for the penalty and quadratised
    // methods, which drop the dampers.
    double damperLoss() const;

    const std::vector<ExactModeCoefficients>& coefficients() const { return coeffs_; }

private:
    // Construction, in stages.
    void buildModeTables(const ModalSolverConfig& config);
    void buildContactShapes(const ModalSolverConfig& config);
    void markCoupledModes(const ModalSolverConfig& config);
    Eigen::MatrixXd stringResponse() const;
    void prepareContactMethods(const ModalSolverConfig& config, Eigen::MatrixXd A);

    void stepSingle();  // one pass per step: many points, the transform path, or a force
    void predictPairStep();  // the pass of a pair's first step, or its second step's projections
    void finishPairStep();   // the point's slope_[0] applied (with one point), the layout advanced
    void predictAtPoints();
    void applyContactForces();
    void endSingleStep();
    int solveContacts();                  // slope_ from s_, b_ by the configured method
    // Point j's scalar contact equation alone (the spline's, or the energy-conserving one), nothing kept.
    ScalarContactSolution solvePointAlone(int j, double s, double b) const;
    // A string held by one spring and nothing else (a sympathetic string on its bridge): its one
    // equation is linear, solved in closed form by solveScalarContact whichever way it is reached.
    bool loneSpring() const
    {
        return P_ == 1 && method_ == ContactMethod::energyConserving && contacts_[0].law.bilateral;
    }
    // On a moving bridge: point j's s with the obstacle raised by `before` at n-1, and b with it
    // raised by `move` more at n+1 (solveOnMovingBridge).
    double sOnBridge(int j, double before) const;
    double bOnBridge(int j, double move) const;
    double aloneForceSlope(int j, double g) const;  // dF/dmove of point j pressing alone, G' = g
    double solvedSlopeDerivative(int j) const;      // G'_j at the last solve's root
    double trialWithSpring(double before, double move, double* slope) const;  // trialOnMovingBridge's
    void findSpringPoint();
    int solveSplines();
    void fullState(std::vector<double>& current, std::vector<double>& previous) const;
    double previousAtRest(int p, double q0) const;  // RT: q^{-1} of mode p released from q0 at rest
    void followStaticGains();  // RT: the static-exact forcing's gains at retuned coefficients
    bool keepModeActions(const double* omega, const double* sigma);  // RT: a retune's motion (retune())
    // RT: count values over the modes, each times its mode's factor; unchanged when there are none.
    static void scaleByModes(double* values, int count, const std::vector<double>& factors)
    {
        if (!factors.empty())
            kernels::scaleEach(factors.data(), values, count);
    }
    // RT: q_p as the solver holds it (p_p = q_p / sqrt(gamma_p) with staticExactForcing), and back.
    double toSolverCoordinate(int p, double q) const { return modeScale_.empty() ? q : q / modeScale_[size_t(p)]; }
    double toModeCoordinate(int p, double value) const
    {
        return modeScale_.empty() ? value : value * modeScale_[size_t(p)];
    }
    void fillStringResponse(Eigen::MatrixXd& A) const;  // RT on the projection path: A into A's storage
    void restartFromModes();                        // RT: the state derived from the modes (contact, pickup, delta, xi)
    void projectActive(const double* qActive, double* u) const;
    // sum_j w_j (psi_j at n + psi_j at n-1) / 2, the obstacles raised by `raise` at n and `raiseBefore` at n-1.
    double contactPotentialEnergy(const double* u, const double* uPrev, bool liveOnly, double raise = 0.0,
                                  double raiseBefore = 0.0) const;
    void measureReach();   // RT: ContactReach::measure() with the solver's tables
    void refreshReach();   // RT: H measured, the live points chosen afresh
    void wakeAll();        // RT: every point live
    // The split step over many modes (EngagedPoints, ModalSolverSplit.cpp).
    void measureTail();         // RT: the high modes' reach per point, after the active modes or kappa changed
    void engageEveryPoint();    // RT, before the prediction: every live point's u^n and u^{n-1} afresh
    void predictSplit();        // the engaged points chosen, their predictions completed
    bool engageReached();       // after a solve: the others that the forces may bring to their obstacle
    void engageMidStep(int j);  // point j engaged after the prediction
    void completePredictions(const int* rows, int count);  // their u~ summed over the high modes too
    void poseContactEquation(int j);                       // RT: point j's s and b from u~ and u^{n-1}
    void keepSteepPrevious();  // RT, before the prediction: q^{n-1} of the steep modes (steepPrevious_)
    // The rows the step solves: the engaged ones on a split step, else the live ones.
    const int* stepRows() const { return splitStep_ ? engaged_.rows() : reach_.liveRows(); }
    int stepCount() const { return splitStep_ ? engaged_.count() : reach_.liveCount(); }
    void projectPoint(int j);  // RT: point j's u^n and u^{n-1} from the state
    void projectPointMidStep(int j);  // RT: the same and u~, after the prediction
    PickupReadout::Forces pickupForces() const { return {shapes_, excitationShape_, contacts_, forceScale_, coeffs_}; }
    // The stepping arrays' weights of pickup k over the active modes (null: no such pickup).
    const double* activePickupWeights(int k) const { return k == 0 ? state_.h() : state_.h2(); }
    void updateCouplings();  // RT: the coupling matrices after the compliance was rescaled

    int M_ = 0;  // modes of the model
    int P_ = 0;
    double dt_ = 0.0;
    double mu_ = 0.0;
    double lengthMetres_ = 0.0;
    double forceScale_ = 0.0;                            // dt^2 / mu
    StampedVector<ExactModeCoefficients> coeffs_;          // all M modes
    StampedVector<ExactModeCoefficients> coeffsReleased_;  // all M modes, releaseSigma added
    double releaseSigma_ = 0.0;
    StampedVector<double> omega_, sigma_;
    StampedVector<double> shapes_;           // P x M, phi_p(x_j) for every mode (projection path)
    StampedVector<char> coupled_;            // mode p touches some contact point
    StampedVector<double> excitationShape_;  // phi_p(x_e), all M modes (empty without excitation)
    std::vector<double> modeScale_;          // sqrt(gamma_p) with staticExactForcing, else empty
    std::vector<double> gainRatio_;          // a retune's new sqrt(gamma_p) over the old (M values)

    // The prediction q~ = a q^n - e q^{n-1} (with an explicit force), and what the pickups read of it.
    ModalState state_;
    double externalForce_ = 0.0;  // N
    // The pickups' readings (the first: the left channel's; the second: the right's, or none).
    std::array<PickupReadout, 2> pickups_;
    kernels::PairReadout pass_;  // the last paired pass's projections of both its steps
    double pairU_ = 0.0;         // the paired step's contact-free u~

    // The contact at the points: r + A G(r) = Phi q~ - u_C^{n-1}, with the dropped modes' spring in series
    // (A + C W), solved by the configured method over the points within reach.
    Eigen::MatrixXd stringCoupling_;   // A = (dt^2/mu) Phi Phi^T W: the string's response at the points
    Eigen::MatrixXd couplingScratch_;  // A + C W, rebuilt on the audio thread by a retune
    Eigen::MatrixXd pointCoupling_;    // (A + C W) W^{-1}: response at the points per newton
    ResidualCompliance compliance_;
    ContactMethod method_ = ContactMethod::energyConserving;
    bool pairedOnBridge_ = false;  // the step on a moving bridge takes the paired path
    ContactSystem system_;  // the energy-conserving Newton
    QuadratisedContact quadratised_;
    std::vector<ContactSpline> splines_;  // per point, the quadratic-spline method's potential
    // u_C^n, u_C^{n-1}, u~ at the points; the equation's s and b, its solution r and slope G(r).
    std::vector<double> uC_, uCPrev_, uTilde_, s_, b_, r_, slope_, penetration_, pointForce_;
    // q^{n-1} of the modes from ModalState::steepFrom(), kept by a prediction on a moving bridge that
    // leaves points out, for projectPointMidStep.
    std::vector<double> steepPrevious_;
    std::vector<ContactPoint> contacts_;
    OwnedGridTransform transform_;
    int lastIterations_ = 0;
    bool lastSolveWasTrial_ = false;
    double lastPenetration_ = 0.0;
    ContactReach reach_;         // the points the step takes
    EngagedPoints engaged_;      // of those, the ones a split step solves
    bool splitStep_ = false;     // this step splits its modes (EngagedPoints)
    // The update q^{n+1} = q~ + (dt^2/mu) Phi^T W f, f = -G(r): from the points with a force.
    std::vector<int> pressing_;
    int springPoint_ = -1;  // the one bilateral point (energy-conserving, coupled), else -1: findSpringPoint()
    bool springsUntried_ = false;  // springs among several points that no trial poses: findSpringPoint()
    // A one-point string's last trial of the step (trialOnMovingBridge) and where it was posed: a
    // solve at the same place takes it (NaN: none yet).
    mutable ScalarContactSolution trial_;
    // A string with a spring and one other point: its last trial, which is its solve, and the point it
    // took (-1: the spring alone); -2 for every other string.
    mutable ContactSystem::SpringTrial springTrial_;
    mutable int springTrialPresser_ = -2;
    mutable double trialBefore_ = std::numeric_limits<double>::quiet_NaN();
    mutable double trialMove_ = std::numeric_limits<double>::quiet_NaN();
};

}  // namespace jawari
