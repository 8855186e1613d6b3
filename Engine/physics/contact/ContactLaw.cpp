#include "physics/contact/ContactLaw.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

namespace jawari
{

namespace
{
// The bilateral law's affine G: the spring's chord K (s + p)/2 with p = s - r, and the damper.
ChordSlope bilateralSlope(const ContactLaw& law, double s, double r)
{
    const double spring = 0.5 * law.stiffness;
    return {-law.stiffness * s + (spring + law.stepDamping) * r, spring + law.stepDamping};
}
}  // namespace

ContactLaw solverLaw(const ContactLaw& law, double dt)
{
    ContactLaw out = law;
    out.stepDamping = law.bilateral ? law.damping / (2.0 * dt) : 0.0;
    if (law.bilateral)
        out.exponent = 1.0;
    return out;
}

double contactPotential(const ContactLaw& law, double penetration)
{
    if (law.bilateral)
        return 0.5 * law.stiffness * penetration * penetration;
    if (penetration <= 0.0)
        return 0.0;
    const double beta = law.exponent + 1.0;
    return law.stiffness / beta * std::pow(penetration, beta);
}

double largestForceDensity(const ContactLaw& law, double weight, double energy)
{
    if (!(energy > 0.0))
        return 0.0;
    const double beta = law.exponent + 1.0;
    const double deepest = std::pow(beta * energy / (law.stiffness * weight), 1.0 / beta);
    return law.stiffness * std::pow(deepest, law.exponent);
}

DividedSeries dividedSeries(double alpha)
{
    DividedSeries series;
    series.exponent = alpha;
    const double beta = alpha + 1.0;
    double c = beta;  // binomial(beta, 1)
    constexpr int n = DividedSeries::kTerms;
    for (int k = 0; k < n; ++k)
    {
        series.c[k] = c;
        c *= (beta - (k + 1.0)) / (k + 2.0);  // binomial(beta, k + 2)
    }
    for (int k = 0; k + 1 < n; ++k)
        series.c1[k] = (k + 1.0) * series.c[k + 1];
    for (int k = 0; k + 2 < n; ++k)
        series.c2[k] = (k + 2.0) * (k + 1.0) * series.c[k + 2];
    double a = 1.0;  // binomial(alpha, 0)
    for (int k = 0; k < n; ++k)
    {
        series.a[k] = a;
        a *= (alpha - k) / (k + 1.0);
    }
    return series;
}

namespace
{

struct Divided
{
    double D = 0.0;    // (p^beta - [s]_+^beta) / (p - s)
    double dD = 0.0;   // dD/dp
    double d2D = 0.0;  // d2D/dp2
};

// sum_k a_k x^k over 16 coefficients by Estrin's scheme: four dependent multiply-adds instead of
// fifteen (the three series of an evaluation run side by side).
inline double polynomial16(const double* a, double x, double x2, double x4, double x8)
{
    static_assert(DividedSeries::kTerms == 16);
    double p[8];
    for (int k = 0; k < 8; ++k)
        p[k] = a[2 * k] + a[2 * k + 1] * x;
    const double q0 = p[0] + p[1] * x2, q1 = p[2] + p[3] * x2, q2 = p[4] + p[5] * x2, q3 = p[6] + p[7] * x2;
    return (q0 + q1 * x4) + (q2 + q3 * x4) * x8;
}

// p^alpha from the anchor's power by the series of (1 + x)^alpha, x = p/x_a - 1, where |x| is
// within reach; else 0.
double anchoredPower(const DividedSeries& series, const KnownPower& anchor, double p)
{
    const double x = (p - anchor.x) * anchor.invX;
    if (!(anchor.xAlpha > 0.0 && std::abs(x) <= DividedSeries::kReach))
        return 0.0;
    const double x2 = x * x, x4 = x2 * x2;
    return anchor.xAlpha * polynomial16(series.a, x, x2, x4, x4 * x4);
}

// D and its derivatives at p = s - r > 0, with sAlpha = [s]_+^alpha and invS = 1/s. Near s, D is
// a function of e = -r/s, so r keeps its full relative precision even where it is far smaller
// than s. Away from s, p^alpha comes from the anchor's series where p is within reach of it, else
// from a pow that becomes the anchor.
Divided divided(const DividedSeries& series, double alpha, double s, double invS, double sAlpha, double r,
                KnownPower& anchor)
{
    if (s > 0.0)
    {
        const double e = -r * invS;
        if (std::abs(e) <= DividedSeries::kReach)
        {
            const double e2 = e * e, e4 = e2 * e2, e8 = e4 * e4;
            const double v = polynomial16(series.c, e, e2, e4, e8);
            const double dv = polynomial16(series.c1, e, e2, e4, e8);
            const double d2v = polynomial16(series.c2, e, e2, e4, e8);
            const double scale = sAlpha * invS;
            return {sAlpha * v, scale * dv, scale * invS * d2v};
        }
    }
    // Away from s (or with s <= 0) nothing cancels: p^beta - s^beta loses at most a few ulps.
    const double p = s - r, invH = -1.0 / r;  // h = p - s = -r
    double pAlpha = anchoredPower(series, anchor, p);
    if (pAlpha == 0.0)
    {
        pAlpha = lawPower(p, alpha);
        anchor = {p, pAlpha, 1.0 / p};
    }
    const double D = (pAlpha * p - sAlpha * std::max(s, 0.0)) * invH;
    const double dD = ((alpha + 1.0) * pAlpha - D) * invH;
    return {D, dD, ((alpha + 1.0) * alpha * pAlpha / p - 2.0 * dD) * invH};
}

}  // namespace

double powerOf(double s, double alpha, const KnownPower* known)
{
    if (!(s > 0.0))
        return 0.0;
    const double x = known != nullptr && known->xAlpha > 0.0 ? (s - known->x) * known->invX : 1.0;
    if (std::abs(x) <= 1e-6)
        // (1 + x)^alpha to second order: the error ~ x^3 <= 1e-18.
        return known->xAlpha * (1.0 + x * alpha * (1.0 + 0.5 * x * (alpha - 1.0)));
    return lawPower(s, alpha);
}

KnownPower rootPower(double s, double sAlpha, double slope, const ContactLaw& law, double r)
{
    const double p = s - r;
    if (law.bilateral || !(p >= 0.5 * s && p > 0.0))
        return {};
    // p^beta = s^beta + D (p - s) with D = -beta G / K, so p^alpha = (s^beta - D r) / p.
    const double D = -(law.exponent + 1.0) * slope / law.stiffness;
    const double invP = 1.0 / p;
    return {p, (sAlpha * s - D * r) * invP, invP};
}

ChordSlope chordSlope(const ContactLaw& law, double s, double r)
{
    if (law.bilateral)
        return bilateralSlope(law, s, r);
    return chordSlope(law, dividedSeries(law.exponent), s, s > 0.0 ? lawPower(s, law.exponent) : 0.0, r);
}

ChordSlope chordSlope(const ContactLaw& law, const DividedSeries& series, double s, double sAlpha, double r,
                      KnownPower* anchor)
{
    if (law.bilateral)
        return bilateralSlope(law, s, r);
    const double p = s - r;  // penetration at n+1
    if (s <= 0.0 && p <= 0.0)
        return {};  // out of contact at both ends
    const double scale = law.stiffness / (law.exponent + 1.0);
    double D = 0.0, dD = 0.0;
    if (p > 0.0)
    {
        KnownPower none;
        const Divided v =
            divided(series, law.exponent, s, s > 0.0 ? 1.0 / s : 0.0, sAlpha, r, anchor != nullptr ? *anchor : none);
        D = v.D;
        dD = v.dD;
    }
    else
    {
        // Leaving: D = (0 - s^beta) / (p - s), and p^alpha = 0.
        D = sAlpha * s / r;
        dD = D / r;
    }
    // G = psi difference / r = -(K/beta) D, and p = s - r: dG/dr = (K/beta) dD/dp.
    return {-scale * D, scale * dD};
}

namespace
{

// Where the solve in contact starts: at or right of the root where a bound allows (from the right,
// Halley's and Newton's steps on the increasing convex Phi descend to the root without passing
// it), else the root of Phi's quadratic model about s. c = k K / beta, d = s - b, sAlpha = s^alpha.
double contactStart(const DividedSeries& series, double alpha, double s, double b, double c, double sAlpha)
{
    const double beta = alpha + 1.0;
    const double d = s - b;
    double p = d;
    if (s > 0.0)
    {
        // The root of Phi's quadratic model about s in e = (p - s)/s, A2 e^2 + A1 e + A0 = 0
        // (A1 > 0, A2 >= 0): the root nearest e = 0 by one Halley step from e = 0,
        // -A0 A1 / (A1^2 - A0 A2), which is it to a relative O((A0 A2 / A1^2)^2), within the model's own
        // error O(e^3) (and needs no square root); Newton's -A0 / A1 where that step would double it.
        const double cs = c * sAlpha;
        const double A2 = cs * series.c[2], A1 = cs * series.c[1] + s, A0 = cs * series.c[0] + b;
        const double A1squared = A1 * A1, denominator = A1squared - A0 * A2;
        const double e = denominator >= 0.5 * A1squared ? -A0 * A1 / denominator : -A0 / A1;
        const double model = s * (1.0 + e);
        if (A0 > 0.0)  // Phi(s) > 0
        {
            // The root is in (0, s). Right of it: the tangent at s, and the root of the linear
            // bound D >= s^alpha (1 + p/s) (alpha >= 1). The nearest of those and the model.
            const double tangent = s - A0 / (c * beta * alpha / 2.0 * sAlpha / s + 1.0);
            const double linear = (d - cs) / (cs / s + 1.0);
            p = tangent > 0.0 ? std::min(tangent, linear) : linear;
            if (model > 0.0 && e > -0.5)
                p = std::min(p, model);
        }
        else
            // The root is in [s, d]: the model where it stays within a factor 2 of s, else the bound
            // D >= p^alpha (c p^alpha = d is right of the root).
            p = e <= 1.0 ? model : std::min(d, std::pow(d / c, 1.0 / alpha));
    }
    else
        // A new contact: D = p^beta / (p - s) >= p^beta / (d - s), so c p^beta = d (d - s) is right
        // of the root.
        p = std::pow(d * (d - s) / c, 1.0 / beta);
    if (!(p > 0.0 && p <= d))
        p = d;
    return p;
}

// One step towards the root of Phi = force - gap (force = c D, gap = r - b) from r, in p = s - r.
struct ContactStep
{
    double step = 0.0;  // in p
    double force = 0.0;
    bool far = false;  // a Newton step in log p
};

ContactStep contactStep(const Divided& v, double c, double s, double r, double b)
{
    const double p = s - r;
    ContactStep out;
    out.force = c * v.D;
    const double gap = r - b;
    const double phi = out.force - gap, dPhi = c * v.dD + 1.0;
    out.far = gap > 4.0 * out.force || (out.force > 4.0 * gap && gap > 0.01 * p);
    if (out.far)
    {
        // Far from the root, where steps in p creep along the curved D: Newton in z = log p on
        // F(z) = log(c D) - log(d - p), which is nearly linear in z (D ~ p^alpha) away from
        // p = d (where the Halley step below serves).
        const double F = std::log(out.force / gap);
        const double dF = p * (v.dD / v.D + 1.0 / gap);
        out.step = p * std::expm1(-F / dF);
    }
    else
    {
        // Halley, -Phi Phi' / (Phi'^2 - Phi Phi''/2): cubic convergence, from the right of the
        // root towards it. Where it would step more than twice Newton's -Phi/Phi', Newton's.
        const double dPhi2 = dPhi * dPhi, denominator = dPhi2 - 0.5 * phi * c * v.d2D;
        out.step = denominator >= 0.5 * dPhi2 ? -phi * dPhi / denominator : -phi / dPhi;
    }
    return out;
}

// The iterations on phi from r in [b, s) to the root: each step contactStep's, kept inside the
// bracket (a step past p = d stops at b, right of the root; one to p <= 0 halves p instead). Leaves v
// at the root (D from its Taylor series after a last small Halley step) and returns the root r.
double iterateToRoot(const DividedSeries& series, double alpha, double s, double invS, double sAlpha, double b,
                     double c, double r, KnownPower& anchor, Divided& v, int& iterations)
{
    constexpr int maxIterations = 100;
    v = divided(series, alpha, s, invS, sAlpha, r, anchor);
    for (int it = 1; it <= maxIterations; ++it)
    {
        iterations = it;
        const double p = s - r;
        const ContactStep st = contactStep(v, c, s, r, b);
        double next = r - st.step;
        bool clamped = false;
        if (!(next >= b))
        {
            next = b;  // p <= d, which is right of the root
            clamped = true;
        }
        else if (!(next < s))
        {
            next = 0.5 * (r + s);  // the root has p > 0: halve p towards it
            clamped = true;
        }
        const double moved = next - r;
        r = next;
        if (!st.far && !clamped && std::abs(moved) <= 1e-6 * std::min(p, std::abs(r) + std::abs(b) + st.force))
        {
            // A Halley step this small: r is the root to ~1e-18 of its scale (cubic convergence). D at it from its
            // Taylor series to the same order, without another evaluation.
            v.D -= moved * (v.dD - 0.5 * moved * v.d2D);
            break;
        }
        v = divided(series, alpha, s, invS, sAlpha, r, anchor);
    }
    return r;
}

}  // namespace

double chordSlopeDerivative(const ContactLaw& law, double s, const ScalarContactSolution& sol)
{
    if (std::isfinite(sol.slopeDerivative))
        return sol.slopeDerivative;
    if (law.bilateral)
        return bilateralSlope(law, s, 0.0).derivative;  // G is affine in r: K/2 + R/(2 dt) everywhere
    const double r = sol.r, p = s - r;
    if (r == 0.0)
        return std::numeric_limits<double>::quiet_NaN();
    if (!(p > 0.0))
        return -sol.slope / r;  // off the obstacle at the root: G = -psi(s) / r
    const double pAlpha =
        sol.penetration.xAlpha > 0.0 && sol.penetration.x == p ? sol.penetration.xAlpha : lawPower(p, law.exponent);
    if (std::abs(r) < 1e-6 * p)
        return 0.5 * law.stiffness * law.exponent * pAlpha / p;
    return (-law.stiffness * pAlpha - sol.slope) / r;
}

ScalarContactSolution solveScalarContact(const ContactLaw& law, double s, double b, double k,
                                         const DividedSeries* series, const KnownPower* known, const NearbyRoot* nearby)
{
    ScalarContactSolution sol;
    if (law.bilateral)
    {
        const ChordSlope atZero = bilateralSlope(law, s, 0.0);
        sol.r = (b - k * atZero.value) / (1.0 + k * atZero.derivative);
        sol.slope = bilateralSlope(law, s, sol.r).value;
        sol.slopeDerivative = atZero.derivative;  // G is affine in r: its slope everywhere
        return sol;
    }
    if (s <= 0.0 && s - b <= 0.0)
    {
        // Out of contact at both ends with the contact-free prediction: G(b) = 0, so r = b exactly.
        sol.r = b;
        return sol;
    }
    const double K = law.stiffness;
    const double alpha = law.exponent;
    const double beta = alpha + 1.0;
    const double c = k * K / beta;
    const double sAlpha = powerOf(s, alpha, known);
    const double psiBefore = K / beta * sAlpha * std::max(s, 0.0);
    // At r = s the string just reaches the obstacle at n+1: phi(s) = s - k psi(s)/s - b = d - c s^alpha.
    if ((s - b) - c * sAlpha <= 0.0)
    {
        // The root has r >= s: the string leaves the obstacle. There G(r) = -psi(s)/r and
        // phi = 0 is r^2 - b r - k psi(s) = 0, whose positive root is taken in a form free of
        // cancellation. (s > 0 here: for s <= 0, phi(s) = s - b > 0 in contact.)
        const double disc = std::sqrt(b * b + 4.0 * k * psiBefore);
        sol.r = b >= 0.0 ? 0.5 * (b + disc) : 2.0 * k * psiBefore / (disc - b);
        sol.slope = -psiBefore / sol.r;
        return sol;
    }

    std::optional<DividedSeries> local;  // built only when needed: constructing it costs a 0.5 KB clear
    if (series == nullptr || series->exponent != alpha)
        series = &local.emplace(dividedSeries(alpha));
    // In contact at n+1: the penetration p = s - r is in (0, d]. The iterate is held as r, which
    // keeps its relative precision when it is far smaller than s.
    KnownPower anchor;
    double r = 0.0;
    if (nearby != nullptr && nearby->r >= b && nearby->r < s)
    {
        r = nearby->r;
        anchor = nearby->power;
    }
    else
        r = std::max(s - contactStart(*series, alpha, s, b, c, sAlpha), b);
    const double invS = s > 0.0 ? 1.0 / s : 0.0;

    Divided v;
    r = iterateToRoot(*series, alpha, s, invS, sAlpha, b, c, r, anchor, v, sol.iterations);
    sol.r = r;
    sol.slope = -K / beta * v.D;
    const double p = s - r;
    sol.penetration = rootPower(s, sAlpha, sol.slope, law, r);
    if (sol.penetration.xAlpha == 0.0 && p > 0.0)
        if (const double pAlpha = anchoredPower(*series, anchor, p); pAlpha > 0.0)
            sol.penetration = {p, pAlpha, 1.0 / p};
    return sol;
}

}  // namespace jawari
