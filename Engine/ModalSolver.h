#pragma once
// The mixed modal scheme of DESIGN.md section 2: M modes, each advanced by its exact update, and
// the energy-conserving contact force at P contact points.
//
//   q~ = a q^n - e q^{n-1}                      (contact-free prediction, exact per mode)
//   r + (dt^2/mu) Phi Phi^T W G(r) = Phi q~ - u_C^{n-1}     (implicit contact, ContactSystem)
//   q^{n+1} = q~ + (dt^2/mu) Phi^T W f,   f = -G(r)
//
// Two ways to reach the contact points:
//  - projection: Phi stored (P x M), O(M P) per step; any points, any M (the few-point path);
//  - transform: the reference grid (M = N - 1, every contact point on a distinct node x_i = i L/N),
//    where Phi Phi^T W is diagonal and q <-> u is a DST-I (FFTW RODFT00), O(N log N) per step.

#include "ContactSystem.h"
#include "ExactOscillator.h"
#include "Obstacle.h"
#include "StringModel.h"

#include <memory>
#include <optional>
#include <vector>

namespace jawari
{

enum class ContactPath
{
    automatic,   // transform when many points can touch and the grid allows it, else projection
    projection,  // the few-point path
    transform    // the DST-I path (reference grid only)
};

// How the contact force of a step is found (DESIGN.md section 4, the methods to chart):
enum class ContactMethod
{
    energyConserving,  // the paper's discrete gradient, solved by Newton (the default)
    quadratised,       // energy quadratisation (scalar auxiliary variable): one linear solve, no Newton
    penalty            // explicit penalty force at u^n: cheap, unstable when K dt^2 is large
};

struct ModalSolverConfig
{
    double lengthMetres = 1.002;
    double linearDensity = 1.17e-3;
    double timeStep = 5e-7;  // s
    ModalTable modes;
    std::vector<ContactPoint> contacts;
    std::vector<double> pickupWeights;  // h_p: the pickup reads sum_p h_p q_p
    ContactPath path = ContactPath::automatic;
    // Where setExternalForce() pushes (the voice's pluck); its modes are kept active.
    std::optional<double> excitationPosition;
    // Extra damping (1/s, every mode) of the second coefficient set, selected by setReleased().
    double releaseSigma = 0.0;
    // Residual compliance (DESIGN.md section 5), P x P row-major, m/N: C_ij = sum over the dropped
    // modes of phi_p(x_i) phi_p(x_j) / (mu w_p^2), the static deflection at i per newton at j. When
    // given (projection path), the dropped modes' quasi-static deflection delta = C W f sits in
    // series with the contact: the contact sees u + delta, and delta^{n+1} = C W f^n (backward
    // Euler on the massless spring: the energy H, spring included, can only decrease, by exactly
    // (delta^{n+1} - delta^{n-1})^T C^{-1} (delta^{n+1} - delta^{n-1}) / 4 a step).
    std::vector<double> contactCompliance;
    ContactMethod method = ContactMethod::energyConserving;
    // Step every mode, even those nothing couples to and that start at rest: the plugin's voices
    // take state across rebuilds (a new pluck or pickup point) and must not drop a ringing mode.
    bool keepEveryMode = false;
};

class ModalSolver
{
public:
    explicit ModalSolver(const ModalSolverConfig& config);  // OFF: tables, Phi, FFTW plans
    ~ModalSolver();
    ModalSolver(const ModalSolver&) = delete;
    ModalSolver& operator=(const ModalSolver&) = delete;

    // OFF/CT: modal displacements at t = 0 with zero velocity; q^{-1} is set from each mode's
    // exact free motion, so without contact the run is the analytic solution (modes damped by
    // more than e^0.5 per step start with q^{-1} = q(+dt) instead, see the .cpp).
    void setInitialDisplacement(const std::vector<double>& modalDisplacement);
    // OFF/CT: an explicit state pair (q^n, q^{n-1}).
    void setState(const std::vector<double>& current, const std::vector<double>& previous);

    void step();  // RT: n -> n+1

    // RT: a point force (N) at the excitation position, applied explicitly from the next step on
    // (part of the prediction: q~ += (dt^2/mu) F phi_e) until set back to 0.
    void setExternalForce(double newtons);
    // RT: switch to the damping set with releaseSigma added (note-off) or back. The state carries
    // over unchanged, so the sound does not jump.
    void setReleased(bool released);
    bool released() const { return released_; }
    // RT: the string part of H^{n-1/2} (no contact part), without allocating.
    double stringEnergy() const;
    // OFF: sum_p h_p^2 / (mu w_p^2): |pickup| <= sqrt(2 H this) for a string of energy H.
    double pickupCompliance() const;

    // RT: new frequencies and damping for every mode (omega, sigma: M values each, rad/s and 1/s),
    // the residual compliance scaled by `complianceScale` from the configured one (1/r^2 when every
    // frequency is scaled by r) and the pickup weights by `pickupScale`. The state (q^n, q^{n-1})
    // carries over. No allocation.
    void retune(const double* omega, const double* sigma, double complianceScale, double pickupScale = 1.0);
    // RT: the law and height of contact point j (the obstacle's automation). No allocation.
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
    void copyStateFrom(ModalSolver& other);

    int modeCount() const { return M_; }
    // Modes actually stepped: a mode that no contact point couples to (phi_p(x_j) = 0 for every j,
    // to 1e-13 of the largest) and that starts at zero (to 1e-13 of the largest mode) stays at
    // zero, so it is skipped (the centre obstacle and centre pluck leave every even mode out).
    // Projection path only.
    int activeModeCount() const { return Ma_; }
    int contactCount() const { return P_; }
    bool usesTransform() const { return transform_ != nullptr; }
    double timeStep() const { return dt_; }

    double pickup() const { return pickup_; }                       // RT: sum h_p q_p^n
    int lastIterations() const { return lastIterations_; }          // RT: contact solve of the last step
    double lastMaxPenetration() const { return lastPenetration_; }  // RT: max_j g_j - u_j^n (m)

    // OFF: the full modal state, q^n (previous = false) or q^{n-1}.
    std::vector<double> modalState(bool previous = false);

    // H^{n-1/2} of DESIGN.md section 2 from the stored (q^n, q^{n-1}), contact part recomputed
    // from the modal state (not from the solver's bookkeeping). CT/OFF.
    struct Energy
    {
        double total = 0.0;
        double contact = 0.0;  // sum_j w_j (psi_j(u^n) + psi_j(u^{n-1})) / 2
    };
    Energy energy();
    // The losses of a step for full states (q^{n+1}, q^{n-1}):
    //   H^{n+1/2} - H^{n-1/2} = -sum mu (1-e_p) ((q^{n+1}-q^{n-1})/(2dt))^2.
    double stepLoss(const double* next, const double* previous) const;

    const std::vector<ExactModeCoefficients>& coefficients() const { return coeffs_; }

private:
    struct Transform;
    // How the stepping arrays hold the state (see kernels::pairStep):
    //  single:       q_ = q^n, qPrev_ = q^{n-1};
    //  pairBoundary: q^n = q_ + (c1 a + c2) phi, q^{n-1} = qPrev_ + c1 phi;
    //  pairMiddle:   q^n = qPrev_ + c1 phi, q^{n-1} = settled_ (q_ holds the pair's raw second step).
    enum class Layout
    {
        single,
        pairBoundary,
        pairMiddle
    };
    void stepSingle();                    // one pass per step: many points, the transform path, or a force
    void stepPaired();                    // one pass per two steps: at most one point (projection)
    void toSingle();                      // RT: rewrites a paired layout as the single one
    double solveOnePoint(double uTilde);  // contact at the single point; returns its slope G
    void fullState(std::vector<double>& current, std::vector<double>& previous) const;
    void compact(const std::vector<double>& current, const std::vector<double>& previous);
    void fillActiveTables();  // RT: the active modes' coefficients, pickup weights and pairing sums
    double previousAtRest(int p, double q0) const;  // RT: q^{-1} of mode p released from q0 at rest
    void restartFromModes();  // RT: the state derived from q_, qPrev_ (contact, pickup, delta, xi)
    void projectActive(const double* qActive, double* u) const;

    int M_ = 0;     // modes of the model
    int Ma_ = 0;    // modes stepped (active)
    int Mpad_ = 0;  // Ma_ rounded up to the kernels' block: the padding modes are zero and stay zero
    int P_ = 0;
    double dt_ = 0.0;
    double mu_ = 0.0;
    double forceScale_ = 0.0;                    // dt^2 / mu
    std::vector<ExactModeCoefficients> coeffs_;  // all M modes
    double releaseSigma_ = 0.0;
    std::vector<double> basePickupWeights_;
    Eigen::MatrixXd baseComplianceC_;  // the configured C (retune scales it)
    Eigen::MatrixXd baseComplianceInverse_, couplingScratch_;
    std::vector<double> omega_, sigma_, pickupWeights_;
    std::vector<double> shapes_;  // P x M, phi_p(x_j) for every mode (projection path)
    std::vector<char> coupled_;   // mode p touches some contact point

    // Stepping arrays over the active modes (all modes in the transform path).
    std::vector<int> active_;
    std::vector<ExactModeCoefficients> activeCoeffs_, activeCoeffsReleased_;
    std::vector<ExactModeCoefficients> coeffsReleased_;  // all M modes, releaseSigma added
    std::vector<int> indexOfMode_;                       // active index of mode p, or -1
    // The stepping arrays live in one 64-byte-aligned block, each `stride_` doubles apart, with the
    // stride staggered modulo 4 KiB: arrays exactly 4 KiB apart make every load alias the stores
    // of the pass (measured: 501 modes padded to 512 ran 1.7x slower).
    std::vector<double> storage_;
    int stride_ = 0;
    double* a_ = nullptr;  // the coefficient set in use (normal or released)
    double* e_ = nullptr;
    double* aNormal_ = nullptr;
    double* eNormal_ = nullptr;
    double* aReleased_ = nullptr;
    double* eReleased_ = nullptr;
    double* h_ = nullptr;
    double* phiE_ = nullptr;  // excitation shape over the active modes
    double* phi_ = nullptr;   // P rows, stride_ apart
    // Single path: q_ = q^n, qPrev_ = q^{n-1}.
    // Paired path (see kernels::pairStep): qPrev_ = X, q_ = Y, settled_ = q^m, with the scalar
    // corrections c1_, c2_; after the first step of a pair q^n = X + c1 phi, q^{n-1} = settled_;
    // after the second q^n = Y + (c1 a + c2) phi, q^{n-1} = X + c1 phi.
    double* q_ = nullptr;
    double* qPrev_ = nullptr;
    double* settled_ = nullptr;
    bool canPair_ = false;
    Layout layout_ = Layout::single;
    double c1_ = 0.0, c2_ = 0.0;
    double pairContact2_ = 0.0, pairPickup2_ = 0.0;
    // sum_p a_p phi_p^2 and sum_p a_p phi_p h_p over the active modes, per damping set.
    double sumAPhiSquared_[2] = {0.0, 0.0}, sumAPhiH_[2] = {0.0, 0.0};
    bool released_ = false;
    std::vector<double> excitationShape_;  // phi_p(x_e), all M modes (empty without excitation)
    double externalForce_ = 0.0;           // N
    double pickupPhiE_ = 0.0;              // (dt^2/mu) h . phi_e

    std::vector<double> pickupPhiW_;  // (dt^2/mu) w_j (h . phi_j)
    Eigen::MatrixXd stringCoupling_;  // A = (dt^2/mu) Phi Phi^T W: the string's response at the points
    Eigen::MatrixXd complianceW_;     // C W (empty without residual compliance)
    Eigen::MatrixXd complianceInverse_;
    std::vector<double> delta_, deltaPrev_;  // quasi-static deflection of the dropped modes, n and n-1
    void advanceCompliance();                // delta^{n+1} = C W f from slope_
    int solveContacts();                     // slope_ from s_, b_ by the configured method
    int solveQuadratised();
    ContactMethod method_ = ContactMethod::energyConserving;
    Eigen::MatrixXd pointCoupling_;  // A' W^{-1}: response at the points per newton
    std::vector<double> savGradient_, savResponse_;
    double xi_ = 0.0, xiPrev_ = 0.0;  // quadratised contact: xi = sqrt(2 V)
    std::vector<double> uC_, uCPrev_, uTilde_, s_, b_, r_, slope_;
    std::vector<ContactPoint> contacts_;
    ContactSystem system_;
    std::unique_ptr<Transform> transform_;
    double pickup_ = 0.0;
    double pickupTilde_ = 0.0;
    int lastIterations_ = 0;
    double lastPenetration_ = 0.0;
};

}  // namespace jawari
