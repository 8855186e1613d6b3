#pragma once
// The paper's scheme (eq. 5) for one mode, multiplied out (docs/design.md section 2):
//   q^{n+1} = a q^n - e q^{n-1} + (dt^2/mu) F^n,
//   a = 2 exp(-sigma dt) cos(wd dt)  (cosh when sigma > omega),  e = exp(-2 sigma dt).
// Exact for the free damped oscillator at any dt.

namespace jawari
{

struct ExactModeCoefficients
{
    double a = 0.0;
    double e = 0.0;
    // The energy of eq. 8 with the paper's C1 = c/D, C2 = w^2/D, C3 = 2 sigma*/D rewritten through
    // the identities D = 2c/(1+e), c = w^2 dt^2 (1+e) / (2 (1+e-a)), sigma* dt = c (1-e)/(1+e):
    //   C1 = (1+e)/2,  C2 = (1+e-a)/dt^2,  dt C3 = 1-e.
    double kineticWeight = 0.0;    // C1
    double potentialWeight = 0.0;  // C2, 1/s^2
    double lossWeight = 0.0;       // dt C3
};

// OFF/CT (pure arithmetic, no allocation: also safe on the audio thread).
ExactModeCoefficients exactCoefficients(double omega, double sigma, double dt);

// 1 + e - a, computed without cancellation (docs/design.md section 2).
double onePlusEMinusA(double omega, double sigma, double dt);

// gamma = (1 + e - a) / (omega dt)^2 = C2 / omega^2: the share of the paper's force gain dt^2/mu that
// makes a force held still deflect the mode by exactly its static compliance F phi / (mu omega^2)
// (the recurrence's fixed point under a constant force is gamma dt^2 F phi / (mu (1 + e - a))). 1 - O(dt^2)
// for omega dt, sigma dt << 1; about 1 / (2 sigma dt) for a mode damped far past a step, about
// 2 (1 - cos omega dt) / (omega dt)^2 for a light mode faster than one. 1 for omega = 0.
double staticForcingGain(double omega, double sigma, double dt);

// The analytic free motion q(t) of q'' + 2 sigma q' + omega^2 q = 0 with q(0) = q0, q'(0) = v0.
double freeDampedMotion(double q0, double v0, double omega, double sigma, double t);

}  // namespace jawari
