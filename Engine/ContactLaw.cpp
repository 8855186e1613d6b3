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
        const double l = std::log1p(-x);
        out.value = K / beta * sAlpha * s * std::expm1(beta * l) / r;
        if (std::abs(x) < 1e-3)
            // dG/dr = K s^(alpha-1) [(beta-1)/2 - (beta-1)(beta-2)/3 x + O(x^2)]
            out.derivative = K * sAlpha / s * ((beta - 1.0) / 2.0 - (beta - 1.0) * (beta - 2.0) / 3.0 * x);
        else
            out.derivative = (-K * sAlpha * std::exp(alpha * l) - out.value) / r;
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
    const double sAlpha = s > 0.0 ? std::pow(s, law.exponent) : 0.0;
    double lo = b;                                   // phi(b) = k G(b) <= 0
    double hi = std::max(b, 0.0) + k * law.stiffness * sAlpha;  // phi(hi) >= 0
    // Start from the warm guess when it lies inside the bracket, else from b.
    double r = guess != nullptr && *guess > lo && *guess < hi ? *guess : b;
    ChordSlope G = chordSlope(law, s, sAlpha, r);
    double phi = r + k * G.value - b;
    if (r == b)
        phi = std::min(phi, 0.0);  // exactly k G(b) <= 0 in exact arithmetic
    else if (phi < 0.0)
        lo = r;
    else if (phi > 0.0)
        hi = r;
    // Converged when phi is at rounding level, or when the next Newton step would move r by less
    // than rounding (stiff contact, phi' >> 1).
    auto converged = [&](double rNow, double phiNow, const ChordSlope& g) {
        const double scale = std::abs(rNow) + std::abs(b);
        return phiNow == 0.0 || std::abs(phiNow) <= 2.0 * eps * (scale + std::abs(k * g.value))
               || std::abs(phiNow) <= 2.0 * eps * scale * (1.0 + k * g.derivative);
    };
    if (r != b && converged(r, phi, G))
    {
        sol.r = r;
        sol.slope = G.value;
        return sol;
    }
    double previousStep = hi - lo;

    for (int it = 1; it <= maxIterations; ++it)
    {
        sol.iterations = it;
        const double dphi = 1.0 + k * G.derivative;
        double next = r - phi / dphi;
        const bool newtonInside = std::isfinite(next) && next > lo && next < hi;
        const bool newtonShrinks = std::abs(next - r) <= 0.5 * std::abs(previousStep);
        if (!(newtonInside && newtonShrinks))
            next = 0.5 * (lo + hi);
        previousStep = next - r;
        r = next;
        G = chordSlope(law, s, sAlpha, r);
        phi = r + k * G.value - b;
        if (phi < 0.0)
            lo = r;
        else if (phi > 0.0)
            hi = r;
        const double scale = std::abs(r) + std::abs(b) + std::abs(k * G.value);
        if (converged(r, phi, G) || hi - lo <= 2.0 * eps * scale || std::abs(previousStep) <= eps * scale)
            break;
    }
    sol.r = r;
    sol.slope = G.value;
    return sol;
}

}  // namespace jawari
