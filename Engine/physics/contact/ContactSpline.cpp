#include "physics/contact/ContactSpline.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace jawari
{

namespace
{

// The largest relative error of the chord of x^alpha over [1, rho] (the same on [a, rho a] for
// any a). The chord over the power is R(X) = (1 + c (X - 1)) / X^alpha with c = (rho^alpha - 1) /
// (rho - 1); R' = 0 at X* = alpha (c - 1) / (c (alpha - 1)), inside [1, rho] for alpha > 1.
double chordError(double alpha, double rho)
{
    if (alpha == 1.0)
        return 0.0;
    const double c = (std::pow(rho, alpha) - 1.0) / (rho - 1.0);
    const double x = std::clamp(alpha * (c - 1.0) / (c * (alpha - 1.0)), 1.0, rho);
    return (1.0 + c * (x - 1.0)) / std::pow(x, alpha) - 1.0;
}

// The largest knot ratio whose chords stay within the tolerance (at most 10): a bisection in
// log rho, 48 halvings of the bracket [1, 10].
double knotRatio(double alpha, double tolerance)
{
    double low = 1.0, high = 10.0;
    if (chordError(alpha, high) <= tolerance)
        return high;
    for (int i = 0; i < 48; ++i)
    {
        const double mid = std::sqrt(low * high);
        (chordError(alpha, mid) <= tolerance ? low : high) = mid;
    }
    return low;
}

}  // namespace

ContactSpline::ContactSpline(const ContactLaw& law)
{
    for (auto* v : {&eta_, &f_, &slope_, &psi_})
        v->reserve(kReservedKnots);
    setLaw(law);
}

void ContactSpline::setLaw(const ContactLaw& law)
{
    if (!(law.stiffness > 0.0) || !(law.exponent >= 1.0))
        throw std::invalid_argument("the quadratic-spline contact needs K > 0 and alpha >= 1");
    law_ = law;
    const double rho = knotRatio(law.exponent, kTolerance);
    eta_.clear();
    eta_.push_back(0.0);
    for (double eta = kLowest; eta_.back() < kHighest; eta *= rho)
        eta_.push_back(eta);
    const size_t n = eta_.size();
    f_.resize(n);
    for (size_t i = 0; i < n; ++i)
        f_[i] = law.stiffness * std::pow(eta_[i], law.exponent);
    slope_.resize(n);
    psi_.assign(n, 0.0);
    for (size_t i = 0; i + 1 < n; ++i)
    {
        const double width = eta_[i + 1] - eta_[i];
        slope_[i] = (f_[i + 1] - f_[i]) / width;
        psi_[i + 1] = psi_[i] + 0.5 * (f_[i] + f_[i + 1]) * width;  // exact for a linear force
    }
    slope_[n - 1] = slope_[n - 2];  // the last segment continues beyond the last knot
}

int ContactSpline::interval(double penetration) const
{
    const auto above = std::upper_bound(eta_.begin(), eta_.end(), penetration);
    return std::max(0, static_cast<int>(above - eta_.begin()) - 1);
}

double ContactSpline::force(double penetration) const
{
    if (!(penetration > 0.0))
        return 0.0;
    const int i = interval(penetration);
    return f_[size_t(i)] + slope_[size_t(i)] * (penetration - eta_[size_t(i)]);
}

double ContactSpline::potential(double penetration) const
{
    if (!(penetration > 0.0))
        return 0.0;
    const auto i = size_t(interval(penetration));
    const double x = penetration - eta_[i];
    return psi_[i] + x * (f_[i] + 0.5 * slope_[i] * x);
}

double ContactSpline::q(double s, double b, double k, double psiS, int knot) const
{
    const double r = s - eta_[size_t(knot)];
    return r * r - b * r + k * (psi_[size_t(knot)] - psiS);
}

// In contact at n+1: the root's penetration p is in (0, d], d = s - b, where h(p) = r + k G(r) - b
// (r = s - p) falls through zero. Bisection over the knots below d gives the knots [lo, hi] around
// it; each step is counted in iterations.
std::pair<int, int> ContactSpline::rootInterval(double s, double b, double k, double psiS, int& iterations) const
{
    const double d = s - b;
    int lo = 0;
    int hi = std::min(knotCount(), interval(d) + 1);
    auto positive = [&](int knot) {
        const double r = s - eta_[size_t(knot)];
        if (r == 0.0)
            return -k * force(s) - b > 0.0;
        return (q(s, b, k, psiS, knot) > 0.0) == (r > 0.0);
    };
    while (hi - lo > 1)
    {
        const int mid = (lo + hi) / 2;
        ++iterations;
        (positive(mid) ? lo : hi) = mid;
    }
    return {lo, hi};
}

ScalarContactSolution ContactSpline::solve(double s, double b, double k) const
{
    ScalarContactSolution sol;
    if (s <= 0.0 && s - b <= 0.0)
    {
        sol.r = b;  // out of contact at both ends
        sol.slopeDerivative = 0.0;
        return sol;
    }
    const double psiS = potential(s);
    if (s > 0.0 && (s - b) * s - k * psiS <= 0.0)
    {
        // Leaving the obstacle: psi(p) = 0 at the root, r^2 - b r - k psi(s) = 0 (ContactLaw.cpp).
        const double disc = std::sqrt(b * b + 4.0 * k * psiS);
        sol.r = b >= 0.0 ? 0.5 * (b + disc) : 2.0 * k * psiS / (disc - b);
        sol.slope = -psiS / sol.r;
        sol.slopeDerivative = psiS / (sol.r * sol.r);  // G = -psi(s)/r
        return sol;
    }
    const int n = knotCount();
    const auto [lo, hi] = rootInterval(s, b, k, psiS, sol.iterations);
    // On interval lo the potential is psi_j + x (f_j + m x / 2), x = p - eta_j = c0 - r with
    // c0 = s - eta_j: Q(r) = a r^2 - B r + C.
    const auto j = size_t(lo);
    const double m = slope_[j], c0 = s - eta_[j];
    const double a = 1.0 + 0.5 * k * m;
    const double B = b + k * (f_[j] + m * c0);
    const double C = k * (psi_[j] + c0 * (f_[j] + 0.5 * m * c0) - psiS);
    const double rHigh = s - eta_[j];
    const double rLow = std::max(hi < n ? s - eta_[size_t(hi)] : -INFINITY, b);
    double r = B / a;  // s on this interval: C = 0 and the other root, r = 0, is the division by r
    if (C != 0.0)
    {
        // s off the interval: r keeps its sign on it, so the quadratic's one root there is the root.
        const double t = 0.5 * (B + std::copysign(std::sqrt(std::max(B * B - 4.0 * a * C, 0.0)), B));
        const double r1 = t / a, r2 = C / t;
        auto outside = [&](double x) { return std::max(rLow - x, x - rHigh); };
        r = outside(r1) <= outside(r2) ? r1 : r2;
    }
    r = std::clamp(r, rLow, rHigh);
    const double p = s - r;
    const bool sameInterval = s >= eta_[j] && (j + 1 == size_t(n) || s <= eta_[j + 1]);
    // The chord slope, without cancellation where s and p share the interval.
    sol.slope = sameInterval ? -(f_[j] + 0.5 * m * (p + s - 2.0 * eta_[j])) : (potential(p) - psiS) / r;
    // G(r) = (psi(s - r) - psi(s)) / r, so G' = (-psi'(p) - G) / r; on s's own interval psi is one
    // quadratic and G' = m / 2 exactly.
    sol.slopeDerivative = sameInterval ? 0.5 * m : (-force(p) - sol.slope) / r;
    sol.r = r;
    return sol;
}

}  // namespace jawari
