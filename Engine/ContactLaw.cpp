#include "ContactLaw.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace jawari
{

double contactPotential(const ContactLaw& law, double penetration)
{
    if (penetration <= 0.0)
        return 0.0;
    const double beta = law.exponent + 1.0;
    return law.stiffness / beta * std::pow(penetration, beta);
}

ChordSlope chordSlope(const ContactLaw& law, double s, double r)
{
    return chordSlope(law, s, s > 0.0 ? std::pow(s, law.exponent) : 0.0, r);
}

ChordSlope chordSlope(const ContactLaw& law, double s, double sAlpha, double r)
{
    const double K = law.stiffness;
    const double alpha = law.exponent;
    const double beta = alpha + 1.0;
    const double sAfter = s - r;  // penetration at n+1
    ChordSlope out;

    if (r == 0.0)
    {
        if (s > 0.0)
        {
            out.value = -K * sAlpha;
            out.derivative = 0.5 * K * alpha * sAlpha / s;
        }
        return out;
    }
    if (s > 0.0 && sAfter > 0.0)
    {
        // In contact at both ends: psi^{n+1} - psi^{n-1} = K/beta s^beta expm1(beta log1p(-r/s)),
        // free of cancellation; (s - r)^alpha = s^alpha exp(alpha log1p(-r/s)) from the same log.
        const double x = r / s;
        const double E = std::expm1(beta * std::log1p(-x));  // (1 - x)^beta - 1
        out.value = K / beta * sAlpha * s * E / r;
        if (std::abs(x) < 1e-3)
            // dG/dr = K s^(alpha-1) [(beta-1)/2 - (beta-1)(beta-2)/3 x + O(x^2)]
            out.derivative = K * sAlpha / s * ((beta - 1.0) / 2.0 - (beta - 1.0) * (beta - 2.0) / 3.0 * x);
        else
            // (s - r)^alpha = s^alpha (1 - x)^beta / (1 - x), from the same expm1.
            out.derivative = (-K * sAlpha * (1.0 + E) / (1.0 - x) - out.value) / r;
        return out;
    }
    // At most one end in contact: one potential is zero, nothing cancels.
    const double psiBefore = s > 0.0 ? K / beta * sAlpha * s : 0.0;
    double psiAfter = 0.0, forceAfter = 0.0;
    if (sAfter > 0.0)
    {
        forceAfter = K * std::pow(sAfter, alpha);
        psiAfter = forceAfter * sAfter / beta;
    }
    out.value = (psiAfter - psiBefore) / r;
    out.derivative = (-forceAfter - out.value) / r;
    return out;
}

ScalarContactSolution solveScalarContact(const ContactLaw& law, double s, double b, double k, const double* guess)
{
    ScalarContactSolution sol;
    if (s <= 0.0 && s - b <= 0.0)
    {
        // Out of contact at both ends with the contact-free prediction: G(b) = 0, so r = b exactly.
        sol.r = b;
        return sol;
    }
    constexpr double eps = std::numeric_limits<double>::epsilon();
    constexpr int maxIterations = 200;
    const double K = law.stiffness;
    const double alpha = law.exponent;
    const double beta = alpha + 1.0;
    const double c = k * K / beta;
    const double d = s - b;
    const double sAlpha = s > 0.0 ? std::pow(s, alpha) : 0.0;
    const double psiBefore = K / beta * sAlpha * std::max(s, 0.0);
    // At r = s the string just reaches the obstacle at n+1: phi(s) = s - k psi(s)/s - b = d - c s^alpha.
    if (d - c * sAlpha <= 0.0)
    {
        // The root has r >= s: the string leaves the obstacle. There G(r) = -psi(s)/r and
        // phi = 0 is r^2 - b r - k psi(s) = 0, whose positive root is taken in a form free of
        // cancellation. (s > 0 here: for s <= 0, phi(s) = s - b > 0 in contact.)
        const double disc = std::sqrt(b * b + 4.0 * k * psiBefore);
        sol.r = b >= 0.0 ? 0.5 * (b + disc) : 2.0 * k * psiBefore / (disc - b);
        sol.slope = -psiBefore / sol.r;
        return sol;
    }

    // In contact at n+1: the root r lies in [b, s), i.e. the penetration p = s - r in (0, d].
    // With D(p) = (p^beta - [s]_+^beta) / (p - s) (the divided difference: G = -(K/beta) D),
    // phi = 0 reads c D(p) = d - p. In z = log p,
    //   F(z) = log(c D(p)) - log(d - p)
    // is strictly increasing, runs from below 0 (p -> 0, since d > c s^alpha) to +inf (p -> d)
    // and is close to linear (D ~ p^alpha), so Newton in z converges in a few steps where Newton in
    // r creeps up a concave curve. D and D' are formed without cancellation near p = s.
    struct Divided
    {
        double D, dD;
    };
    auto divided = [&](double p, double z) -> Divided {
        if (s <= 0.0)
        {
            const double pBeta = std::exp(beta * z);
            const double D = pBeta / (p - s);
            return {D, (beta * pBeta / p - D) / (p - s)};
        }
        const double e = (p - s) / s;
        if (std::abs(e) >= 0.5)
        {
            // Far from s nothing cancels in p^beta - s^beta (relative error below 3 eps): one exp.
            const double pBeta = std::exp(beta * z);
            const double D = (pBeta - sAlpha * s) / (p - s);
            return {D, (beta * pBeta / p - D) / (p - s)};
        }
        if (std::abs(e) < 1e-3)
            return {beta * sAlpha * (1.0 + (beta - 1.0) / 2.0 * e + (beta - 1.0) * (beta - 2.0) / 6.0 * e * e),
                    beta * sAlpha / s * ((beta - 1.0) / 2.0 + (beta - 1.0) * (beta - 2.0) / 3.0 * e)};
        const double E = std::expm1(beta * std::log1p(e));  // (p/s)^beta - 1
        const double D = sAlpha * s * E / (p - s);
        return {D, (beta * sAlpha * (1.0 + E) / (1.0 + e) - D) / (p - s)};
    };

    // Fast path: at a high rate the previous steps' extrapolated r is close to the root, where
    // Newton in r converges quadratically. Up to three steps inside [b, s); otherwise on below.
    if (guess != nullptr && *guess > b && *guess < s)
    {
        double r = *guess;
        double lo = b, hi = s;
        for (int it = 1; it <= 3; ++it)
        {
            const ChordSlope G = chordSlope(law, s, sAlpha, r);
            const double phi = r + k * G.value - b;
            const double scale = std::abs(r) + std::abs(b);
            sol.iterations = it;
            if (std::abs(phi) <= 2.0 * eps * (scale + std::abs(k * G.value))
                || std::abs(phi) <= 2.0 * eps * scale * (1.0 + k * G.derivative))
            {
                sol.r = r;
                sol.slope = G.value;
                return sol;
            }
            (phi < 0.0 ? lo : hi) = r;
            const double next = r - phi / (1.0 + k * G.derivative);
            // Only worth pursuing when the guess was already close (quadratic convergence from
            // there); at audio-like rates it often is not, and the log-penetration Newton below is
            // then the quicker way.
            if (!(next > lo && next < hi) || (it == 1 && std::abs(next - r) > 1e-3 * scale))
                break;
            r = next;
        }
    }

    // One evaluation at p = d/2 says which half holds the root (phi = (d - p) - c D(p)).
    const double pMid = 0.5 * d;
    const Divided atMid = divided(pMid, std::log(pMid));
    if (c * atMid.D < d - pMid)
    {
        // Soft: the root is in p in (d/2, d), r in (b, b + d/2), where phi is nearly linear in r:
        // Newton in r, kept inside that bracket by bisection.
        double lo = b, hi = s - pMid;  // phi(lo) <= 0 < phi(hi)
        double r = guess != nullptr && *guess > lo && *guess < hi ? *guess : 0.5 * (lo + hi);
        ChordSlope G = chordSlope(law, s, sAlpha, r);
        for (int it = 1; it <= maxIterations; ++it)
        {
            sol.iterations = it;
            const double phi = r + k * G.value - b;
            const double scale = std::abs(r) + std::abs(b) + std::abs(k * G.value);
            if (std::abs(phi) <= 2.0 * eps * scale)
                break;
            if (phi < 0.0)
                lo = r;
            else
                hi = r;
            double next = r - phi / (1.0 + k * G.derivative);
            if (!(next > lo && next < hi))
                next = 0.5 * (lo + hi);
            if (std::abs(next - r) <= eps * scale || hi - lo <= 2.0 * eps * scale)
            {
                r = next;
                G = chordSlope(law, s, sAlpha, r);
                break;
            }
            r = next;
            G = chordSlope(law, s, sAlpha, r);
        }
        sol.r = r;
        sol.slope = G.value;
        return sol;
    }

    // Stiff: the root is in p in (0, d/2]. Newton in z = log p, started from the warm guess when
    // it is in range, else from the balance c p^alpha = d.
    double p = 0.0;
    if (guess != nullptr && s - *guess > 0.0 && s - *guess <= pMid)
        p = s - *guess;
    else
        p = std::min(pMid, std::pow(d / c, 1.0 / alpha));
    if (!(p > 0.0))
        p = pMid;
    double zLow = -std::numeric_limits<double>::infinity();  // F < 0 there
    double pHigh = pMid;                                     // F >= 0 there
    double z = std::log(p);
    Divided dv = p == pMid ? atMid : divided(p, z);
    for (int it = 1; it <= maxIterations; ++it)
    {
        sol.iterations = it;
        const double logForce = std::log(c * dv.D), logGap = std::log(d - p);
        const double F = logForce - logGap;
        // F is known to about eps (|log c D| + |log (d - p)|): below that, p is the root to rounding.
        if (std::abs(F) <= 4.0 * eps * (1.0 + std::abs(logForce) + std::abs(logGap)))
            break;
        if (F < 0.0)
            zLow = z;
        else if (F > 0.0)
            pHigh = p;
        else
            break;
        const double dF = p * dv.dD / dv.D + p / (d - p);
        const double step = F / dF;
        if (std::abs(step) <= 4.0 * eps)
            break;  // p is the root to rounding (and D belongs to this p)
        double zNext = z - step;
        double pNext = std::exp(zNext);
        if (!(zNext > zLow) || !(pNext < pHigh) || !std::isfinite(zNext))
        {
            // Newton left the bracket: halve the side it left through.
            pNext = F < 0.0 ? 0.5 * (p + pHigh) : 0.5 * (p + std::exp(zLow));
            zNext = std::log(pNext);
        }
        z = zNext;
        p = pNext;
        dv = divided(p, z);
        if (pHigh - std::exp(zLow) <= 4.0 * eps * pHigh)
            break;
    }
    sol.r = s - p;
    sol.slope = -K / beta * dv.D;
    return sol;
}

}  // namespace jawari
