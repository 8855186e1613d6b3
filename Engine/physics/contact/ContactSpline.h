#pragma once
// The quadratic-spline contact (after Bhanuprakash, van Walstijn and Chatziioannou, 2024;
// docs/design.md section 4): the contact potential psi(eta) = K/(alpha+1) eta^(alpha+1) of a
// penetration eta is replaced by the C1 piecewise quadratic whose derivative, the force, runs
// linearly between knots where it equals K eta^alpha:
//
//   eta_0 = 0 < eta_1 = kLowest < eta_2 < ... ,  eta_{i+1} = rho eta_i  (geometric: the same
//   relative force error on every interval), beyond the last knot the last segment continues.
//
// rho is the largest ratio that keeps the spline's force within kTolerance (relative) of
// K eta^alpha over [kLowest, kHighest]; below kLowest the force is the chord from 0 (its
// potential there is below 1e-13 of the potential at kLowest x 1e4 for the paper's law).
//
// With a piecewise quadratic potential the energy-conserving scheme's scalar equation
// r + k G(r) = b (ContactLaw.h) is a quadratic in r on each interval: the root's interval is found
// by bisection over the knots (the equation is monotone) and the root in closed form. No Newton,
// and the discrete energy balance is exact for the spline's potential. Decoupled points only (one
// point, or the reference grid).

#include "physics/contact/ContactLaw.h"

#include <cstddef>
#include <utility>
#include <vector>

namespace jawari
{

class ContactSpline
{
public:
    static constexpr double kTolerance = 0.01;  // relative force error over [kLowest, kHighest]
    static constexpr double kLowest = 1e-9;     // m of penetration
    static constexpr double kHighest = 1e-3;    // m: beyond any scene's penetration

    // Capacity kept for the knots: every exponent up to 4 (the plugin's range, 180 knots at most)
    // is rebuilt without allocating.
    static constexpr int kReservedKnots = 192;

    explicit ContactSpline(const ContactLaw& law);  // OFF: the knots for the law
    // RT for exponents up to 4 (no allocation; about 200 pows): the knots for a new law.
    void setLaw(const ContactLaw& law);

    const ContactLaw& law() const { return law_; }
    int knotCount() const { return static_cast<int>(eta_.size()); }
    double force(double penetration) const;      // RT: the spline's force per metre (N/m)
    double potential(double penetration) const;  // RT: its potential (J/m), 0 for penetration <= 0

    // RT: r + k G(r) = b with G the chord slope of the spline's potential along u (s = g - u^{n-1},
    // as solveScalarContact). iterations: the bisection's steps over the knots.
    ScalarContactSolution solve(double s, double b, double k) const;

private:
    int interval(double penetration) const;  // i with eta_i <= penetration < eta_{i+1} (the last extends)
    // Q(r) = r (r + k G(r) - b) at the knot's penetration (p = s - r = eta_knot), given psi(s).
    double q(double s, double b, double k, double psiS, int knot) const;
    std::pair<int, int> rootInterval(double s, double b, double k, double psiS, int& iterations) const;

    ContactLaw law_;
    std::vector<double> eta_;    // knots
    std::vector<double> f_;      // the force at each knot: K eta_i^alpha
    std::vector<double> slope_;  // the force's slope on interval i
    std::vector<double> psi_;    // the potential at each knot
};

}  // namespace jawari
