#pragma once
// The regularised contact of DESIGN.md section 1 and its energy-conserving discrete gradient
// (section 2, after Bilbao, Torin & Chatziioannou 2015).
//
//   psi(u) = K/(alpha+1) [g - u]_+^(alpha+1),   f = -dpsi/du = K [g - u]_+^alpha   (per metre)
//
// Everything here is RT: pure arithmetic, no allocation.

namespace jawari
{

struct ContactLaw
{
    double stiffness = 1e13;  // K, N/m^(1+alpha)
    double exponent = 1.3;    // alpha >= 1
};

// psi as a function of the penetration g - u (J/m).
double contactPotential(const ContactLaw& law, double penetration);

// With s = g - u^{n-1} and r = u^{n+1} - u^{n-1}, the chord slope of psi along u,
//   G(r) = (psi(u^{n-1} + r) - psi(u^{n-1})) / r      (G(0) = psi'(u^{n-1})),
// and dG/dr. G <= 0 and is nondecreasing (psi is convex); the contact force is f = -G.
// The difference of potentials is formed as s^(alpha+1) expm1((alpha+1) log1p(-r/s)), which
// keeps full relative accuracy as r -> 0 (no cancellation), so f r = -(psi^{n+1} - psi^{n-1})
// holds to rounding and the energy balance with it.
struct ChordSlope
{
    double value = 0.0;
    double derivative = 0.0;
};
ChordSlope chordSlope(const ContactLaw& law, double s, double r);
// The same with sAlpha = [s]_+^alpha precomputed (it is fixed during a solve).
ChordSlope chordSlope(const ContactLaw& law, double s, double sAlpha, double r);

// Solves  r + k G(r) = b  (k > 0): the scalar contact equation of DESIGN.md section 2.
// phi(r) = r + k G(r) - b is strictly increasing, phi(b) <= 0 and
// phi(max(b, 0) + k K [s]_+^alpha) >= 0, so [b, that] brackets the root; Newton steps that
// leave the bracket or stall are replaced by bisection, so it always converges.
struct ScalarContactSolution
{
    double r = 0.0;
    double slope = 0.0;  // G(r): the force per metre is -slope
    int iterations = 0;  // Newton/bisection evaluations after the first
};
// `guess` (optional) starts the iteration when it lies inside the bracket: the previous step's r
// is usually within a few ulps of the answer at a high rate.
ScalarContactSolution solveScalarContact(const ContactLaw& law, double s, double b, double k,
                                         const double* guess = nullptr);

}  // namespace jawari
