#include "physics/ContactSystem.h"

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
    G_.setZero(P);
    dG_.setZero(P);
    phi_.setZero(P);
    trialPhi_.setZero(P);
    step_.setZero(P);
    AG_.setZero(P);
    trial_.setZero(P);
    r_.setZero(P);
    J_.setZero(P, P);
    lu_ = Eigen::PartialPivLU<Eigen::MatrixXd>(P);
    previousR_.assign(points_.size(), 0.0);
    olderR_.assign(points_.size(), 0.0);
    previousContact_.assign(points_.size(), 0);
    olderContact_.assign(points_.size(), 0);
}

void ContactSystem::setLaw(int j, const ContactLaw& law)
{
    points_[size_t(j)].law = law;
    if (series_[size_t(j)].exponent != law.exponent)
    {
        series_[size_t(j)] = dividedSeries(law.exponent);  // no allocation: a fixed-size table
        known_[size_t(j)] = {};                            // powers of the old exponent
        anchors_[size_t(j)] = {};
    }
}

void ContactSystem::setCoupling(const Eigen::MatrixXd& couplingA)
{
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
}

double ContactSystem::residual(const double* s, const double* b, const Eigen::VectorXd& r, Eigen::VectorXd& phi)
{
    const Eigen::Index P = r.size();
    for (Eigen::Index j = 0; j < P; ++j)
    {
        const ChordSlope c =
            chordSlope(points_[j].law, series_[size_t(j)], s[j], sAlpha_[size_t(j)], r[j], &anchors_[size_t(j)]);
        G_[j] = c.value;
        dG_[j] = c.derivative;
    }
    phi.noalias() = A_ * G_;
    phi += r;
    for (Eigen::Index j = 0; j < P; ++j)
        phi[j] -= b[j];
    return phi.lpNorm<Eigen::Infinity>();
}

void ContactSystem::gaussSeidelSweep(const double* s, const double* b, Eigen::VectorXd& r)
{
    const Eigen::Index P = r.size();
    for (Eigen::Index j = 0; j < P; ++j)
    {
        double others = 0.0;
        for (Eigen::Index i = 0; i < P; ++i)
            if (i != j)
                others +=
                    A_(j, i) * chordSlope(points_[i].law, series_[size_t(i)], s[i], sAlpha_[size_t(i)], r[i]).value;
        r[j] = solveScalarContact(points_[j].law, s[j], b[j] - others, A_(j, j), &series_[size_t(j)]).r;
    }
}

int ContactSystem::solve(const double* s, const double* b, double* r, double* slope)
{
    if (diagonal_)
        return solveDecoupled(s, b, r, slope);
    // The points that touch at n-1 or with the contact-free prediction at n+1.
    const Eigen::Index P = static_cast<Eigen::Index>(points_.size());
    int touching = 0;
    Eigen::Index last = -1;
    for (Eigen::Index j = 0; j < P; ++j)
        if (s[j] > 0.0 || s[j] - b[j] > 0.0)
        {
            ++touching;
            last = j;
        }
    int iterations = 0;
    if (touching == 1 && solveOneTouching(last, s, b, r, slope, iterations))
        return iterations;
    if (touching == 0)
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
    const Eigen::Index P = static_cast<Eigen::Index>(points_.size());
    const auto sol =
        solveScalarContact(points_[a].law, s[a], b[a], A_(a, a), &series_[size_t(a)], &known_[size_t(a)][1]);
    for (Eigen::Index i = 0; i < P; ++i)
        if (i != a && !(s[i] - (b[i] - A_(i, a) * sol.slope) <= 0.0))
            return false;
    for (Eigen::Index i = 0; i < P; ++i)
        if (i != a)
            record(i, b[i] - A_(i, a) * sol.slope, 0.0, KnownPower{}, r, slope);
    record(a, sol.r, sol.slope, sol.penetration, r, slope);
    iterations = sol.iterations;
    return true;
}

// No point can touch: every r is the contact-free b, every force 0.
void ContactSystem::releaseAll(const double* b, double* r, double* slope)
{
    for (size_t j = 0; j < points_.size(); ++j)
    {
        r[j] = b[j];
        slope[j] = 0.0;
        previousContact_[j] = olderContact_[j] = 0;
        known_[j] = {KnownPower{}, known_[j][0]};
    }
}

// The P x P Newton on phi(r) = r + A G(r) - b, warm-started from the previous steps where each
// point was in contact, with a backtracking line search on |phi| and Gauss-Seidel sweeps of exact
// scalar solves where the line search stalls.
int ContactSystem::solveCoupled(const double* s, const double* b, double* r, double* slope)
{
    constexpr int maxIterations = 100;
    const Eigen::Index P = static_cast<Eigen::Index>(points_.size());
    for (Eigen::Index j = 0; j < P; ++j)
        sAlpha_[size_t(j)] = powerOf(s[j], points_[j].law.exponent, &known_[size_t(j)][1]);
    for (Eigen::Index j = 0; j < P; ++j)
        r_[j] = olderContact_[j] ? 2.0 * previousR_[j] - olderR_[j] : previousContact_[j] ? previousR_[j] : b[j];
    // G_ and dG_ always hold the slopes at the last point residual() was called at.
    double norm = residual(s, b, r_, phi_);
    int it = 0;
    while (norm > 0.0 && it < maxIterations)
    {
        ++it;
        if (!newtonStep(s, b, norm))
            break;
    }
    for (Eigen::Index j = 0; j < P; ++j)  // every exit above leaves G_ at r_
        record(j, r_[j], G_[j], rootPower(s[j], sAlpha_[size_t(j)], G_[j], points_[j].law, r_[j]), r, slope);
    return it;
}

// One iteration of the coupled Newton from r_ (residual `norm`, updated). False when converged:
// the residual or the step is at rounding, or a sweep no longer lowers the residual.
bool ContactSystem::newtonStep(const double* s, const double* b, double& norm)
{
    constexpr double eps = std::numeric_limits<double>::epsilon();
    const Eigen::Index P = r_.size();
    AG_.noalias() = A_ * G_;
    const double scale = r_.lpNorm<Eigen::Infinity>()
                         + Eigen::Map<const Eigen::VectorXd>(b, P).lpNorm<Eigen::Infinity>()
                         + AG_.lpNorm<Eigen::Infinity>();
    if (norm <= 4.0 * eps * scale)
        return false;
    J_.noalias() = A_ * dG_.asDiagonal();
    J_.diagonal().array() += 1.0;
    lu_.compute(J_);
    step_.noalias() = lu_.solve(phi_);  // into preallocated storage: no temporary
    step_ = -step_;
    double t = 1.0;
    bool accepted = false;
    for (int halving = 0; halving < 40; ++halving, t *= 0.5)
    {
        trial_ = r_ + t * step_;
        const double trialNorm = residual(s, b, trial_, trialPhi_);
        if (std::isfinite(trialNorm) && trialNorm <= (1.0 - 1e-4 * t) * norm)
        {
            accepted = true;
            break;
        }
    }
    if (accepted)
    {
        // The trial's residual and slopes (G_, dG_) are those of the new point.
        const double moved = (t * step_).lpNorm<Eigen::Infinity>();
        r_.swap(trial_);
        phi_.swap(trialPhi_);
        norm = phi_.lpNorm<Eigen::Infinity>();
        return moved > eps * scale;
    }
    // Stalled line search (kinks of [.]_+ at alpha near 1): a sweep of exact scalar solves.
    gaussSeidelSweep(s, b, r_);
    const double before = norm;
    norm = residual(s, b, r_, phi_);
    return norm < before;
}

}  // namespace jawari
