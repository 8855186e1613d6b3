#pragma once
// The regularised contact of docs/design.md section 1 and its energy-conserving discrete gradient
// (section 2, after Bilbao, Torin & Chatziioannou 2015).
//
//   psi(u) = K/(alpha+1) [g - u]_+^(alpha+1),   f = -dpsi/du = K [g - u]_+^alpha   (per metre)
//
// A bilateral law is a linear spring-damper the string never leaves (the damped thread of van
// Walstijn, Bridges & Mehes, DAFx-16): psi = (K/2) (g - u)^2 on both sides (alpha = 1) and a damper
// f = -R du/dt, discretised as -R (u^{n+1} - u^{n-1}) / (2 dt), which only dissipates.
//
// Everything here is RT: pure arithmetic, no allocation.

#include <cmath>
#include <limits>

namespace jawari
{

struct ContactLaw
{
    double stiffness = 1e13;  // K, N/m^(1+alpha)
    double exponent = 1.3;    // alpha >= 1 (1 when bilateral)
    bool bilateral = false;   // a spring-damper the string never leaves (above)
    double damping = 0.0;     // R, kg/(s m): the bilateral law's damper, per metre of string
    // R / (2 dt): the damper's force per metre per metre of r = u^{n+1} - u^{n-1}, set by the solver
    // from `damping` and its time step (solverLaw); 0 outside a solver.
    double stepDamping = 0.0;
};

// x^alpha for x > 0, as the solves take a law's powers: alpha = 1.5 (the sitar's laws) as x sqrt(x),
// within about an ulp of pow at a fraction of its cost; any other alpha by pow.
inline double lawPower(double x, double alpha)
{
    return alpha == 1.5 ? x * std::sqrt(x) : std::pow(x, alpha);
}

// The law as a solver of time step dt uses it: stepDamping = damping / (2 dt).
ContactLaw solverLaw(const ContactLaw& law, double dt);

// psi as a function of the penetration g - u (J/m); (K/2) p^2 on both sides when bilateral.
double contactPotential(const ContactLaw& law, double penetration);

// The largest force density K p^alpha a point of weight w (m) can bear while its energy w psi(p)
// stays at most `energy` (J): p <= ((alpha + 1) energy / (K w))^(1/(alpha + 1)).
double largestForceDensity(const ContactLaw& law, double weight, double energy);

// The series of the divided difference D(p) = (p^beta - s^beta) / (p - s) about p = s:
//   D = s^alpha sum_k c_k e^k,   e = (p - s) / s,   c_k = binomial(beta, k + 1),
// used where |e| <= kReach: no pow and no cancellation there. It depends on alpha only, so it is
// built once per law (ContactSystem keeps one per point), not per solve.
struct DividedSeries
{
    static constexpr int kTerms = 16;
    static constexpr double kReach = 0.125;  // |c_16| 0.125^16 < 1e-16 c_0 for alpha in [1, 4]
    double exponent = -1.0;                  // the alpha it was built for
    double c[kTerms] = {};
    double c1[kTerms] = {};  // of dD/de: (k + 1) c_{k+1}
    double c2[kTerms] = {};  // of d2D/de2: (k + 2)(k + 1) c_{k+2}
    // (1 + x)^alpha = sum_k a_k x^k, a_k = binomial(alpha, k): a power x^alpha from one known
    // within kReach of it, without a pow (the solve's later iterates, near its first).
    double a[kTerms] = {};
};
DividedSeries dividedSeries(double alpha);

// With s = g - u^{n-1} and r = u^{n+1} - u^{n-1}, the chord slope of psi along u,
//   G(r) = (psi(u^{n-1} + r) - psi(u^{n-1})) / r      (G(0) = psi'(u^{n-1})),
// and dG/dr. G <= 0 and is nondecreasing (psi is convex); the contact force is f = -G.
// Where both ends are in contact and |r/s| <= DividedSeries::kReach, G comes from the series of
// the divided difference (no pow, no cancellation as r -> 0); elsewhere p^beta - s^beta cancels by
// a few ulps at most. So f r = -(psi^{n+1} - psi^{n-1}) holds to rounding and the energy balance
// with it.
struct ChordSlope
{
    double value = 0.0;
    double derivative = 0.0;
};
ChordSlope chordSlope(const ContactLaw& law, double s, double r);
// A power x^alpha known at some x > 0, used two ways:
//  - an earlier solve's penetration: the contact point's s two steps later is that step's p to
//    ~1e-12, so s^alpha follows from it without a pow (powerOf);
//  - an anchor, the latest pow made during a solve: a penetration within DividedSeries::kReach of x
//    takes its power from it by the series a_k instead of another pow.
struct KnownPower
{
    double x = 0.0;
    double xAlpha = 0.0;  // x^alpha, or 0 if unknown
    double invX = 0.0;    // 1/x
    bool operator==(const KnownPower&) const = default;
};
// The same with the law's series and sAlpha = [s]_+^alpha given (both fixed during a solve), and
// optionally an anchor the evaluation uses and renews (kept per point by the caller).
ChordSlope chordSlope(const ContactLaw& law, const DividedSeries& series, double s, double sAlpha, double r,
                      KnownPower* anchor = nullptr);

// [s]_+^alpha, from `known` without a pow where s is within 1e-6 of its x (optional).
double powerOf(double s, double alpha, const KnownPower* known);
// The penetration p = s - r at the root and p^alpha from the chord slope there (p^beta = s^beta +
// D (p - s), D = -beta G / K), where p >= s/2 (elsewhere that would cancel: xAlpha = 0).
KnownPower rootPower(double s, double sAlpha, double slope, const ContactLaw& law, double r);

// Solves  r + k G(r) = b  (k > 0): the scalar contact equation of docs/design.md section 2.
// A bilateral law's G is affine: r = (b + k K s) / (1 + k (K/2 + R/(2 dt))) at once. Out of contact, or leaving it (the root has the string off the obstacle at n+1), the root is in
// closed form. In contact at n+1 it is found in the penetration p = s - r in (0, d], d = s - b:
//   Phi(p) = (k K / beta) D(p) + p - d = 0.
// Phi is increasing and convex for alpha >= 1 (D is the mean of psi' between s and p, and the
// third derivative of psi is >= 0), so Halley's and Newton's steps from the right of the root
// descend to it without passing it. Started at or right of the root where a bound allows (the
// tangent at s, a linear bound on D, a power balance on a new contact), else from Phi's quadratic
// model about s, it takes about two evaluations of D, each one pow at most (none near s, where
// the series serves, nor within DividedSeries::kReach of the solve's last pow, its anchor); Newton
// in log p takes the steps from a start far off.
struct ScalarContactSolution
{
    double r = 0.0;
    double slope = 0.0;  // G(r): the force per metre is -slope
    // dG/dr at the root where the solver has it in closed form (ContactSpline; a bilateral law's
    // K/2 + R/(2 dt), the same at every r), else NaN.
    double slopeDerivative = std::numeric_limits<double>::quiet_NaN();
    int iterations = 0;  // Halley or Newton steps
    // The root's penetration p = s - r with p^alpha, formed without a pow: from D (p^beta = s^beta +
    // D (p - s)) where p >= s/2, else from the solve's last pow where p is within reach of it. xAlpha
    // is 0 when the string is off the obstacle at n+1 or neither applies.
    KnownPower penetration;
};
// A start for the solve below near its root: the root of the same point's equation with the same s
// and a nearby b, moved along its slope (dr/db = 1 / (1 + k G')), and that root's penetration power
// as the solve's first anchor. Then one evaluation of D usually ends it (SharedBody's trials, one
// per bridge displacement tried).
struct NearbyRoot
{
    double r = std::numeric_limits<double>::quiet_NaN();
    KnownPower power;
};
// `series` (optional) is dividedSeries(law.exponent), built once by the caller; without it, or if
// it was built for another exponent, it is built here. `known` (optional): see KnownPower. `nearby`
// (optional): a start in contact, taken where it lies in the root's bracket [b, s).
ScalarContactSolution solveScalarContact(const ContactLaw& law, double s, double b, double k,
                                         const DividedSeries* series = nullptr, const KnownPower* known = nullptr,
                                         const NearbyRoot* nearby = nullptr);
// dG/dr at the root `sol` of the scalar equation above, from the solution alone. A bilateral law's
// G is affine in r, its slope K/2 + R/(2 dt) everywhere. A unilateral law's: G(r) = (psi(s - r) -
// psi(s)) / r, so G' = (-psi'(p) - G) / r with p = s - r, and psi''(p) / 2 where r is too small
// against p for that quotient. One pow at most (none where the solve knew p^alpha). The solution's
// own slopeDerivative where it has one.
double chordSlopeDerivative(const ContactLaw& law, double s, const ScalarContactSolution& sol);

// One point's equation with everything its solve takes, handed between the string that poses it
// and a caller that solves many strings' equations together (ContactLanes.h).
struct ScalarContactRequest
{
    ContactLaw law;
    double s = 0.0, b = 0.0, k = 0.0;
    const DividedSeries* series = nullptr;  // dividedSeries(law.exponent)
    KnownPower known;
};
inline ScalarContactSolution solveScalarContact(const ScalarContactRequest& q)
{
    return solveScalarContact(q.law, q.s, q.b, q.k, q.series, &q.known);
}

}  // namespace jawari
