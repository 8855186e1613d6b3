#include "physics/contact/ContactSystem.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace jawari
{

void ContactSystem::prepare(const std::vector<ContactPoint>& points, Eigen::MatrixXd couplingA)
{
    points_ = points;
    series_.clear();
    known_.assign(points_.size(), {});
    anchors_.assign(points_.size(), {});
    sAlpha_.assign(points_.size(), 0.0);
    for (const auto& p : points_)
        series_.push_back(dividedSeries(p.law.exponent));
    A_ = std::move(couplingA);
    const Eigen::Index P = static_cast<Eigen::Index>(points_.size());
    diagonal_ = true;
    for (Eigen::Index i = 0; i < P; ++i)
        for (Eigen::Index j = 0; j < P; ++j)
            if (i != j && std::abs(A_(i, j)) > 1e-12 * std::sqrt(std::abs(A_(i, i) * A_(j, j))))
                diagonal_ = false;
    if (diagonal_)
        A_ = Eigen::MatrixXd(A_.diagonal().asDiagonal());
    for (auto* v : {&G_, &r_, &rT_, &bT_, &GT_, &dGT_, &phiT_, &trialT_, &trialPhiT_, &stepT_, &AGT_})
        v->setZero(P);
    AT_.setZero(P, P);
    JT_.setZero(P, P);
    active_.clear();
    active_.reserve(points_.size());
    allPoints_.resize(points_.size());
    for (size_t j = 0; j < points_.size(); ++j)
        allPoints_[j] = static_cast<int>(j);
    inActive_.assign(points_.size(), 0);
    previousR_.assign(points_.size(), 0.0);
    olderR_.assign(points_.size(), 0.0);
    previousContact_.assign(points_.size(), 0);
    olderContact_.assign(points_.size(), 0);
    lastAlone_.point = -1;
}

void ContactSystem::setLaw(int j, const ContactLaw& law)
{
    points_[size_t(j)].law = law;
    lastAlone_.point = -1;  // an equation (and a trial) of the old law
    if (series_[size_t(j)].exponent != law.exponent)
    {
        series_[size_t(j)] = dividedSeries(law.exponent);  // no allocation: a fixed-size table
        known_[size_t(j)] = {};                            // powers of the old exponent
        anchors_[size_t(j)] = {};
    }
}

void ContactSystem::setCoupling(const Eigen::MatrixXd& couplingA)
{
    lastAlone_.point = -1;  // an equation (and a trial) of the old coupling
    if (diagonal_)
        for (Eigen::Index j = 0; j < A_.rows(); ++j)
            A_(j, j) = couplingA(j, j);
    else
        A_ = couplingA;  // same size: Eigen copies into the existing storage
}

void ContactSystem::reset()
{
    std::fill(previousContact_.begin(), previousContact_.end(), 0);
    std::fill(olderContact_.begin(), olderContact_.end(), 0);
    std::fill(known_.begin(), known_.end(), std::array<KnownPower, 2>{});
    std::fill(anchors_.begin(), anchors_.end(), KnownPower{});
    lastAlone_.point = -1;
}

int ContactSystem::solve(const double* s, const double* b, double* r, double* slope)
{
    return solve(s, b, r, slope, allPoints_.data(), size());
}

int ContactSystem::solve(const double* s, const double* b, double* r, double* slope, const int* points, int count)
{
    tookTrial_ = false;
    const int iterations = solveListed(s, b, r, slope, points, count);
    lastAlone_.trial = false;  // good for one solve
    return iterations;
}

ScalarContactSolution ContactSystem::solveAlone(int j, double s, double b) const
{
    const ScalarContactSolution solution = solveNearLast(j, s, b);
    lastAlone_.trial = true;
    return solution;
}

// Point j's equation alone; where it was solved last in this step with the same s (the caller's
// trials, or a solve at another bridge), from that root moved along its slope.
ScalarContactSolution ContactSystem::solveNearLast(int j, double s, double b) const
{
    const ContactLaw& law = points_[size_t(j)].law;
    const ScalarContactSolution& last = lastAlone_.solution;
    NearbyRoot nearby;
    if (lastAlone_.point == j && lastAlone_.s == s && last.slope != 0.0 && last.r < s)
    {
        const double drdb = 1.0 / (1.0 + A_(j, j) * chordSlopeDerivative(law, s, last));
        nearby = {last.r + (b - lastAlone_.b) * drdb, last.penetration};
    }
    const KnownPower& known = known_[size_t(j)][1];
    lastAlone_ = {j, s, b, known,
                  solveScalarContact(law, s, b, A_(j, j), &series_[size_t(j)], &known,
                                     std::isfinite(nearby.r) ? &nearby : nullptr)};
    return lastAlone_.solution;
}

int ContactSystem::solveListed(const double* s, const double* b, double* r, double* slope, const int* points, int count)
{
    if (diagonal_)
        return solveDecoupled(s, b, r, slope);
    listed_ = points;
    listedCount_ = count;
    // The candidates: the points that touch at n-1 or with the contact-free prediction at n+1.
    active_.clear();
    for (int k = 0; k < count; ++k)
    {
        const int j = points[k];
        if (points_[size_t(j)].law.bilateral || s[j] > 0.0 || s[j] - b[j] > 0.0)
            active_.push_back(j);
    }
    int iterations = 0;
    if (!active_.empty() && solveOnePresser(s, b, r, slope, iterations))
        return iterations;
    if (active_.empty())
    {
        releaseAll(b, r, slope);
        return 0;
    }
    return solveCoupled(s, b, r, slope);
}

// Phi Phi^T W diagonal (the reference grid): P independent scalar solves.
int ContactSystem::solveDecoupled(const double* s, const double* b, double* r, double* slope)
{
    int most = 0;
    for (int j = 0; j < size(); ++j)
    {
        ScalarContactRequest request;
        scalarRequest(j, s[j], b[j], request);
        const auto sol = solveScalarContact(request);
        recordScalar(j, sol);
        r[j] = sol.r;
        slope[j] = sol.slope;
        most = std::max(most, sol.iterations);
    }
    return most;
}

void ContactSystem::scalarRequest(int j, double s, double b, ScalarContactRequest& request) const
{
    // Field by field: a caller's request is read back field by field (ContactLaneBatch::add).
    request.law.stiffness = points_[size_t(j)].law.stiffness;
    request.law.exponent = points_[size_t(j)].law.exponent;
    request.law.bilateral = points_[size_t(j)].law.bilateral;
    request.law.damping = points_[size_t(j)].law.damping;
    request.law.stepDamping = points_[size_t(j)].law.stepDamping;
    request.s = s;
    request.b = b;
    request.k = A_(j, j);
    request.series = &series_[size_t(j)];
    const KnownPower& known = known_[size_t(j)][1];
    request.known.x = known.x;
    request.known.xAlpha = known.xAlpha;
    request.known.invX = known.invX;
}

void ContactSystem::recordScalar(int j, const ScalarContactSolution& solution)
{
    auto& known = known_[size_t(j)];
    known[1] = known[0];
    known[0] = solution.penetration;
}

// Point j's solution and its bookkeeping: the warm start's history and the known powers.
void ContactSystem::record(Eigen::Index j, double rj, double slopej, const KnownPower& power, double* r, double* slope)
{
    r[j] = rj;
    slope[j] = slopej;
    olderR_[j] = previousR_[j];
    olderContact_[j] = previousContact_[j];
    previousR_[j] = rj;
    previousContact_[j] = slopej != 0.0;
    auto& known = known_[size_t(j)];
    known[1] = known[0];
    known[0] = power;
}

// One point a can touch: its own scalar equation (the others' G are 0), and the others moved by
// its force, r_i = b_i - A_ia G_a. That is the exact solution of the coupled system if they stay
// off the obstacle at both ends (s_i <= 0 already; s_i - r_i <= 0 is checked), for then their G is
// exactly 0. False (nothing written) when one of them would touch: the coupled Newton decides.
bool ContactSystem::solveOneTouching(Eigen::Index a, const double* s, const double* b, double* r, double* slope,
                                     int& iterations)
{
    // Where the caller's trial posed this very equation, its solution, kept: not solved again.
    const bool tried = lastAlone_.trial && lastAlone_.point == a && lastAlone_.s == s[a] && lastAlone_.b == b[a]
                       && lastAlone_.known == known_[size_t(a)][1];
    const auto sol = tried ? lastAlone_.solution : solveNearLast(int(a), s[a], b[a]);
    for (int k = 0; k < listedCount_; ++k)
    {
        const int i = listed_[k];
        if (i != a && (points_[size_t(i)].law.bilateral || !(s[i] - (b[i] - A_(i, a) * sol.slope) <= 0.0)))
            return false;
    }
    for (int k = 0; k < listedCount_; ++k)
    {
        const int i = listed_[k];
        if (i != a)
            record(i, b[i] - A_(i, a) * sol.slope, 0.0, KnownPower{}, r, slope);
    }
    record(a, sol.r, sol.slope, sol.penetration, r, slope);
    iterations = sol.iterations;
    tookTrial_ = tried;
    return true;
}

// Most steps with several candidates have one point that presses and others its force keeps off
// (a string on a bridge presses at the apex while the prediction dips its neighbours). The system's
// root is unique (A = S W with S positive semidefinite, G nondecreasing), so a point whose scalar
// solution leaves every other point off the obstacle at both ends gives the root exactly. The
// others must then be off at n-1 (s <= 0), so the one tried is the candidate in contact at n-1 if
// there is exactly one, or the one the prediction pushes deepest (largest s - b) if there is none.
bool ContactSystem::solveOnePresser(const double* s, const double* b, double* r, double* slope, int& iterations)
{
    int deepest = -1, inContact = -1, bilateral = -1;
    for (int a : active_)
    {
        if (points_[size_t(a)].law.bilateral)
        {
            if (bilateral >= 0)
                return false;  // two bilateral points: the Newton
            bilateral = a;
            continue;
        }
        if (deepest < 0 || s[a] - b[a] > s[deepest] - b[deepest])
            deepest = a;
        if (s[a] > 0.0)
        {
            if (inContact >= 0)
                return false;  // two in contact at n-1: the Newton
            inContact = a;
        }
    }
    const int presser = inContact >= 0 ? inContact : deepest;
    if (bilateral >= 0)
        return solveWithBilateral(bilateral, presser, s, b, r, slope, iterations);
    return solveOneTouching(presser, s, b, r, slope, iterations);
}

// One bilateral point t (the damped thread) and at most one point a that can touch (-1: none).
// t's chord slope is affine, G_t = g0 + c r_t, so its equation gives G_t = G0 + gamma G_a, and a's
// becomes a scalar contact equation r_a + (A_aa + A_at gamma) G_a = b_a - A_at G0 (the Schur
// complement: k' > 0). Exact, as solveOneTouching, if every other point stays off its obstacle at
// both ends; false (nothing written) when one would touch: the coupled Newton decides.
bool ContactSystem::solveWithBilateral(int t, int a, const double* s, const double* b, double* r, double* slope,
                                       int& iterations)
{
    const SpringTrial solved = trialWithSpring(t, a, s[t], b[t], a >= 0 ? s[a] : 0.0, a >= 0 ? b[a] : 0.0, false);
    // Point i moved by a's force (nothing without a) and the spring's.
    auto moved = [&](int i) { return b[i] - (a >= 0 ? A_(i, a) * solved.Ga : 0.0) - A_(i, t) * solved.Gt; };
    for (int k = 0; k < listedCount_; ++k)
    {
        const int i = listed_[k];
        if (i != a && i != t && !(s[i] - moved(i) <= 0.0))
            return false;
    }
    for (int k = 0; k < listedCount_; ++k)
    {
        const int i = listed_[k];
        if (i != a && i != t)
            record(i, moved(i), 0.0, KnownPower{}, r, slope);
    }
    recordSpringTrial(t, a, solved, r, slope);
    iterations = solved.a.iterations;
    return true;
}

// The Schur complement above. Its derivatives, with both b rising by one: G0 by c / stiffen, a's b'
// by 1 - A_at c / stiffen, so r_a by db' / (1 + k' G_a'), G_a by G_a' dr_a, and G_t = G0 + gamma G_a
// by dG0 + gamma dG_a.
ContactSystem::SpringTrial ContactSystem::trialWithSpring(int t, int a, double st, double bt, double sa, double ba,
                                                          bool derivatives) const
{
    const ChordSlope thread = chordSlope(points_[size_t(t)].law, st, 0.0);
    const double g0 = thread.value, c = thread.derivative;
    const double stiffen = 1.0 + A_(t, t) * c;
    SpringTrial out;
    out.Gt = (g0 + c * bt) / stiffen;
    out.dGt = c / stiffen;
    out.rt = (bt - A_(t, t) * g0) / stiffen;  // as solveWithBilateral's, with a's force below
    if (a < 0)
        return out;
    const double gamma = -c * A_(t, a) / stiffen;
    const double k = A_(a, a) + A_(a, t) * gamma;
    const ScalarContactSolution sol = solveScalarContact(points_[size_t(a)].law, sa, ba - A_(a, t) * out.Gt, k,
                                                         &series_[size_t(a)], &known_[size_t(a)][1]);
    out.a = sol;
    out.Ga = sol.slope;
    if (derivatives)
    {
        const double dGa = chordSlopeDerivative(points_[size_t(a)].law, sa, sol);
        out.dGa = dGa * (1.0 - A_(a, t) * out.dGt) / (1.0 + k * dGa);
        out.dGt += gamma * out.dGa;
    }
    out.Gt += gamma * out.Ga;
    out.rt = (bt - A_(t, t) * g0 - A_(t, a) * sol.slope) / stiffen;
    return out;
}

void ContactSystem::recordSpringTrial(int t, int a, const SpringTrial& trial, double* r, double* slope)
{
    if (a >= 0)
        record(a, trial.a.r, trial.a.slope, trial.a.penetration, r, slope);
    record(t, trial.rt, trial.Gt, KnownPower{}, r, slope);
}

// No point can touch: every r is the contact-free b, every force 0.
void ContactSystem::releaseAll(const double* b, double* r, double* slope)
{
    for (int k = 0; k < listedCount_; ++k)
    {
        const size_t j = size_t(listed_[k]);
        r[j] = b[j];
        slope[j] = 0.0;
        previousContact_[j] = olderContact_[j] = 0;
        known_[j] = {KnownPower{}, known_[j][0]};
    }
}


// The coupled points in contact. Every point outside the candidates T has G = 0 exactly as long as
// it stays off the obstacle at n+1, and is then moved by T's forces alone, r_i = b_i - A_iT G_T; so
// the Newton runs on T only (|T| x |T|), and a point that T's forces bring into contact joins T and
// the Newton goes on from where it stopped. The root is that of the full P x P system.
int ContactSystem::solveCoupled(const double* s, const double* b, double* r, double* slope)
{
    std::fill(inActive_.begin(), inActive_.end(), 0);
    for (int j : active_)
        admit(j, s, b[j]);
    int iterations = 0;
    do
        iterations += solveActive(s, b);
    while (admitNewlyTouching(s, b));
    for (int k = 0; k < listedCount_; ++k)
    {
        const int j = listed_[k];
        if (inActive_[size_t(j)])
            record(j, r_[j], G_[j], rootPower(s[j], sAlpha_[size_t(j)], G_[j], points_[j].law, r_[j]), r, slope);
        else
            record(j, r_[j], 0.0, KnownPower{}, r, slope);
    }
    return iterations;
}

// Point j joins T: its [s]_+^alpha for the solve, and its start, warm from the previous steps where
// it was in contact (linear extrapolation over two), else `start`.
void ContactSystem::admit(int j, const double* s, double start)
{
    inActive_[size_t(j)] = 1;
    sAlpha_[size_t(j)] = powerOf(s[j], points_[j].law.exponent, &known_[size_t(j)][1]);
    r_[j] = olderContact_[j] ? 2.0 * previousR_[j] - olderR_[j] : previousContact_[j] ? previousR_[j] : start;
}

// Every point outside T moved by T's forces; those that would then touch at n+1 join T (true if any).
bool ContactSystem::admitNewlyTouching(const double* s, const double* b)
{
    const int n = static_cast<int>(active_.size());
    bool added = false;
    for (int m = 0; m < listedCount_; ++m)
    {
        const int j = listed_[m];
        if (inActive_[size_t(j)])
            continue;
        double moved = b[j];
        for (int k = 0; k < n; ++k)
            moved -= A_(j, active_[size_t(k)]) * G_[active_[size_t(k)]];
        r_[j] = moved;
        if (s[j] - moved > 0.0)
        {
            active_.push_back(j);
            admit(j, s, moved);
            added = true;
        }
    }
    return added;
}

// The Newton on phi_T(r_T) = r_T + A_TT G_T(r_T) - b_T from r_ on T, with a backtracking line search
// on |phi| and Gauss-Seidel sweeps of exact scalar solves where the line search stalls. Leaves
// r_ and G_ (at r_) on T; returns the iterations.
int ContactSystem::solveActive(const double* s, const double* b)
{
    constexpr int maxIterations = 100;
    const int n = static_cast<int>(active_.size());
    for (int k = 0; k < n; ++k)
    {
        const int j = active_[size_t(k)];
        rT_[k] = r_[j];
        bT_[k] = b[j];
        for (int l = 0; l < n; ++l)
            AT_(k, l) = A_(j, active_[size_t(l)]);
    }
    double norm = residual(s, rT_, phiT_);
    int it = 0;
    while (norm > 0.0 && it < maxIterations)
    {
        ++it;
        if (!newtonStep(s, norm))
            break;
    }
    for (int k = 0; k < n; ++k)  // every exit above leaves GT_ at rT_
    {
        r_[active_[size_t(k)]] = rT_[k];
        G_[active_[size_t(k)]] = GT_[k];
    }
    return it;
}

// phi = r + A_TT G(r) - b_T on T, with GT_ and dGT_ written at r; returns |phi|_inf.
double ContactSystem::residual(const double* s, const Eigen::VectorXd& r, Eigen::VectorXd& phi)
{
    const int n = static_cast<int>(active_.size());
    for (int k = 0; k < n; ++k)
    {
        const int j = active_[size_t(k)];
        const ChordSlope c =
            chordSlope(points_[j].law, series_[size_t(j)], s[j], sAlpha_[size_t(j)], r[k], &anchors_[size_t(j)]);
        GT_[k] = c.value;
        dGT_[k] = c.derivative;
    }
    phi.head(n).noalias() = AT_.topLeftCorner(n, n) * GT_.head(n);
    phi.head(n) += r.head(n) - bT_.head(n);
    return phi.head(n).lpNorm<Eigen::Infinity>();
}

// One sweep of exact scalar solves over T, each point against the others' current forces.
void ContactSystem::gaussSeidelSweep(const double* s)
{
    const int n = static_cast<int>(active_.size());
    for (int k = 0; k < n; ++k)  // the slopes at rT_ (a failed line search left its last trial's)
    {
        const int j = active_[size_t(k)];
        GT_[k] = chordSlope(points_[j].law, series_[size_t(j)], s[j], sAlpha_[size_t(j)], rT_[k]).value;
    }
    for (int k = 0; k < n; ++k)
    {
        const int j = active_[size_t(k)];
        double others = 0.0;
        for (int l = 0; l < n; ++l)
            if (l != k)
                others += AT_(k, l) * GT_[l];
        rT_[k] = solveScalarContact(points_[j].law, s[j], bT_[k] - others, AT_(k, k), &series_[size_t(j)]).r;
        GT_[k] = chordSlope(points_[j].law, series_[size_t(j)], s[j], sAlpha_[size_t(j)], rT_[k]).value;
    }
}

namespace
{
// Solves J x = y in place (J: n x n, column-major with leading dimension ld, overwritten by its LU
// factors; y overwritten by x) by Gaussian elimination with partial pivoting. Eigen's decompositions
// reallocate when n changes from solve to solve; this works in the caller's storage.
void solveInPlace(double* J, int ld, int n, double* y)
{
    auto at = [&](int i, int k) -> double& { return J[static_cast<ptrdiff_t>(k) * ld + i]; };
    for (int k = 0; k < n; ++k)
    {
        int pivot = k;
        for (int i = k + 1; i < n; ++i)
            if (std::abs(at(i, k)) > std::abs(at(pivot, k)))
                pivot = i;
        if (pivot != k)
        {
            for (int c = k; c < n; ++c)
                std::swap(at(k, c), at(pivot, c));
            std::swap(y[k], y[pivot]);
        }
        for (int i = k + 1; i < n; ++i)
        {
            const double m = at(i, k) / at(k, k);
            for (int c = k + 1; c < n; ++c)
                at(i, c) -= m * at(k, c);
            y[i] -= m * y[k];
        }
    }
    for (int k = n - 1; k >= 0; --k)
    {
        double v = y[k];
        for (int c = k + 1; c < n; ++c)
            v -= at(k, c) * y[c];
        y[k] = v / at(k, k);
    }
}
}  // namespace

// One iteration of the Newton on T from rT_ (residual `norm`, updated). False when converged: the
// residual or the step is at rounding, or a sweep no longer lowers the residual.
bool ContactSystem::newtonStep(const double* s, double& norm)
{
    constexpr double eps = std::numeric_limits<double>::epsilon();
    const int n = static_cast<int>(active_.size());
    const auto A = AT_.topLeftCorner(n, n);
    AGT_.head(n).noalias() = A * GT_.head(n);
    const double scale = rT_.head(n).lpNorm<Eigen::Infinity>() + bT_.head(n).lpNorm<Eigen::Infinity>()
                         + AGT_.head(n).lpNorm<Eigen::Infinity>();
    if (norm <= 4.0 * eps * scale)
        return false;
    // J = I + A_TT diag(dG), factorised in place with the step.
    auto J = JT_.topLeftCorner(n, n);
    J.noalias() = A * dGT_.head(n).asDiagonal();
    J.diagonal().array() += 1.0;
    stepT_.head(n) = -phiT_.head(n);
    solveInPlace(JT_.data(), static_cast<int>(JT_.rows()), n, stepT_.data());
    double t = 1.0;
    bool accepted = false;
    for (int halving = 0; halving < 40; ++halving, t *= 0.5)
    {
        trialT_.head(n) = rT_.head(n) + t * stepT_.head(n);
        const double trialNorm = residual(s, trialT_, trialPhiT_);
        if (std::isfinite(trialNorm) && trialNorm <= (1.0 - 1e-4 * t) * norm)
        {
            accepted = true;
            break;
        }
    }
    if (accepted)
    {
        // The trial's residual and slopes (GT_, dGT_) are those of the new point.
        const double moved = t * stepT_.head(n).lpNorm<Eigen::Infinity>();
        rT_.head(n) = trialT_.head(n);
        phiT_.head(n) = trialPhiT_.head(n);
        norm = phiT_.head(n).lpNorm<Eigen::Infinity>();
        return moved > eps * scale;
    }
    // Stalled line search (kinks of [.]_+ at alpha near 1): a sweep of exact scalar solves.
    gaussSeidelSweep(s);
    const double before = norm;
    norm = residual(s, rT_, phiT_);
    return norm < before;
}

}  // namespace jawari
