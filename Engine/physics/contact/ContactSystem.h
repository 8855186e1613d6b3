#pragma once
// The implicit contact solve of docs/design.md section 2 for P coupled points:
//   r + A G(r) = b,   A = (dt^2/mu) Phi Phi^T W,   G_j the chord slope of point j.
// A diagonal A splits into P scalar solves (the reference grid: Phi Phi^T W = I). Otherwise a
// Newton iteration on the points that can touch this step (a point off the obstacle at both ends
// has no force, so it only follows the others), with a backtracking line search on |phi|, falling
// back to nonlinear Gauss-Seidel sweeps of scalar solves when the line search stalls.

#include "physics/contact/ContactLaw.h"
#include "physics/contact/Obstacle.h"

#include <Eigen/Dense>

#include <array>
#include <vector>

namespace jawari
{

class ContactSystem
{
public:
    // OFF: sizes every workspace so solve() never allocates.
    void prepare(const std::vector<ContactPoint>& points, Eigen::MatrixXd couplingA);

    int size() const { return static_cast<int>(points_.size()); }
    bool isDiagonal() const { return diagonal_; }
    const Eigen::MatrixXd& coupling() const { return A_; }

    // Forget the warm-start history (new initial state). RT.
    void reset();

    // RT: a new law for point j (the obstacle's stiffness or exponent automated); no allocation.
    void setLaw(int j, const ContactLaw& law);
    // RT: a new coupling matrix of the same size (the residual compliance rescaled by a retune).
    // The diagonal/coupled decision made by prepare() stands: a rescaled compliance keeps it.
    void setCoupling(const Eigen::MatrixXd& couplingA);

    // RT. s_j = g_j - u_j^{n-1}, b_j = u~_j - u_j^{n-1}. Writes r and the slopes G_j(r_j)
    // (force per metre -G_j). Returns the iteration count (max over points when decoupled).
    int solve(const double* s, const double* b, double* r, double* slope);
    // RT: the same over the listed points only (`count` indices, ascending); the others must be off
    // their obstacle at n-1 and n+1 whatever the listed ones do (out of the string's reach), and
    // their r and slope are left as they are. No allocation.
    int solve(const double* s, const double* b, double* r, double* slope, const int* points, int count);
    // RT: the two halves of solve() for point j of a diagonal system, for a caller that solves many
    // strings' points together (StringBank): its scalar equation for s_j, b_j, and the bookkeeping
    // of its solution (the known powers the next solves start from).
    void scalarRequest(int j, double s, double b, ScalarContactRequest& request) const;
    void recordScalar(int j, const ScalarContactSolution& solution);
    // RT: point j's scalar equation alone (every other point's force 0), as solve() poses it when j
    // is the one point that presses: a caller's trial (SharedBody's secant). Only its solution is
    // kept, until the next solve(), which takes it unsolved where it poses this very equation (j the
    // one point that presses, with the same s, b and known powers: the same bits). tookTrial():
    // whether the last solve() did.
    ScalarContactSolution solveAlone(int j, double s, double b) const;
    bool tookTrial() const { return tookTrial_; }
    // RT, at each step's start: a point's scalar equation is started from its last root only within
    // the step (solveAlone, and a solve with one point pressing), where s is the same.
    void beginStep() { lastAlone_.point = -1; }

    // RT: solveWithBilateral's equations for the bilateral point t and the point a that can touch (-1:
    // none), every other point's force 0, nothing kept (a caller's trial, as solveAlone): G_t, G_a, and
    // with `derivatives` theirs as b_t and b_a rise together (dG/db; NaN where G_a' has no closed
    // form; 0 without).
    struct SpringTrial
    {
        double Gt = 0.0, Ga = 0.0, dGt = 0.0, dGa = 0.0;
        double rt = 0.0;
        ScalarContactSolution a;  // the point's (r = b, G = 0 without one)
    };
    SpringTrial trialWithSpring(int t, int a, double st, double bt, double sa, double ba,
                                bool derivatives = true) const;
    // RT: that trial kept as solveWithBilateral keeps its solution (r, G and their history), for a
    // caller whose solve it is: a string with the spring and the one point, both listed (a < 0: the
    // spring alone listed).
    void recordSpringTrial(int t, int a, const SpringTrial& trial, double* r, double* slope);

private:
    int solveListed(const double* s, const double* b, double* r, double* slope, const int* points, int count);
    ScalarContactSolution solveNearLast(int j, double s, double b) const;  // j's scalar equation alone
    int solveDecoupled(const double* s, const double* b, double* r, double* slope);
    bool solveOnePresser(const double* s, const double* b, double* r, double* slope, int& iterations);
    bool solveOneTouching(Eigen::Index a, const double* s, const double* b, double* r, double* slope, int& iterations);
    bool solveWithBilateral(int t, int a, const double* s, const double* b, double* r, double* slope, int& iterations);
    void releaseAll(const double* b, double* r, double* slope);
    int solveCoupled(const double* s, const double* b, double* r, double* slope);
    void admit(int j, const double* s, double start);
    bool admitNewlyTouching(const double* s, const double* b);
    int solveActive(const double* s, const double* b);
    // On the candidates T (active_): phi = r + A_TT G(r) - b_T with GT_, dGT_ written at r; |phi|_inf.
    double residual(const double* s, const Eigen::VectorXd& r, Eigen::VectorXd& phi);
    void gaussSeidelSweep(const double* s);
    bool newtonStep(const double* s, double& norm);
    void record(Eigen::Index j, double rj, double slopej, const KnownPower& power, double* r, double* slope);

    std::vector<ContactPoint> points_;
    std::vector<DividedSeries> series_;  // per point, for its law's exponent
    // Per point, the penetration powers of the last two scalar solves: [0] the latest. The older
    // one's p is this step's s (ContactLaw.h, KnownPower).
    std::vector<std::array<KnownPower, 2>> known_;
    // The last scalar equation of one point solved alone (solveNearLast), with the known powers it was
    // posed with, and its solution (point -1: none). Within the step it starts the point's next
    // equation with the same s. `trial`: it was a caller's trial (solveAlone), which the next solve()
    // takes where it poses this very equation; good for one solve. A new step, law, coupling or
    // history forgets it.
    struct AloneSolve
    {
        int point = -1;
        double s = 0.0, b = 0.0;
        KnownPower known;
        ScalarContactSolution solution;
        bool trial = false;
    };
    mutable AloneSolve lastAlone_;
    bool tookTrial_ = false;
    std::vector<double> sAlpha_;       // [s_j]_+^alpha of the coupled solve in progress
    std::vector<KnownPower> anchors_;  // per point, the coupled solve's latest pow (ContactLaw.h)
    Eigen::MatrixXd A_;
    bool diagonal_ = true;
    Eigen::VectorXd G_, r_;  // per point: the solve's slopes and r
    // The candidates T (point indices, capacity P) and the Newton's workspace on them: the first |T|
    // entries of each vector, the top-left |T| x |T| of each matrix, indexed by position in T.
    std::vector<int> active_;
    std::vector<int> allPoints_;                     // 0 .. P-1
    const int* listed_ = nullptr;                 // the points of the solve in progress
    int listedCount_ = 0;
    std::vector<char> inActive_;
    Eigen::VectorXd rT_, bT_, GT_, dGT_, phiT_, trialT_, trialPhiT_, stepT_, AGT_;
    Eigen::MatrixXd AT_, JT_;
    // Warm start of the coupled Newton: the last two steps' r where the point was in contact.
    std::vector<double> previousR_, olderR_;
    std::vector<char> previousContact_, olderContact_;
};

}  // namespace jawari
