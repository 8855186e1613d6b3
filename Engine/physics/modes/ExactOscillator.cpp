#include "physics/modes/ExactOscillator.h"

#include <cmath>

namespace jawari
{
namespace
{
// cos-like and sin(x)/x-like parts of the damped motion over time t:
// underdamped C = cos(wd t), S = sin(wd t)/wd; overdamped C = cosh(wh t), S = sinh(wh t)/wh.
struct Propagator
{
    double C, S;
};

Propagator propagator(double omega, double sigma, double t)
{
    const double disc = omega * omega - sigma * sigma;
    if (disc >= 0.0)
    {
        const double wd = std::sqrt(disc);
        const double x = wd * t;
        return {std::cos(x), x == 0.0 ? t : std::sin(x) / wd};
    }
    const double wh = std::sqrt(-disc);
    const double x = wh * t;
    return {std::cosh(x), x == 0.0 ? t : std::sinh(x) / wh};
}
}  // namespace

double onePlusEMinusA(double omega, double sigma, double dt)
{
    const double E = std::exp(-sigma * dt);
    const double disc = omega * omega - sigma * sigma;
    if (disc >= 0.0)
    {
        const double s = std::sin(0.5 * std::sqrt(disc) * dt);
        return (1.0 - E) * (1.0 - E) + 4.0 * E * s * s;
    }
    // Overdamped: 1 + e - a = (1 - E e^{x})(1 - E e^{-x}) with x = wh dt, and
    // sigma dt - x = dt omega^2 / (sigma + wh) exactly, so both factors are expm1's.
    const double wh = std::sqrt(-disc);
    return std::expm1(-dt * omega * omega / (sigma + wh)) * std::expm1(-dt * (sigma + wh));
}

namespace
{
// A mode so overdamped that cosh(wh t) overflows while e^{-sigma t} underflows (0 * inf) is
// stepped from its two real roots, r1,2 = -sigma +- wh with r1 = -omega^2 / (sigma + wh) exactly.
// The test is on sigma |t| (>= wh |t|) and its own function: the usual path below compiles, and so
// rounds, as it did without it.
constexpr double kOverflowGuard = 700.0;

bool beyondCosh(double omega, double sigma, double t)
{
    return sigma * std::abs(t) > kOverflowGuard && sigma > omega;
}

// a = 2 E cosh(wh dt) = E e^{x} + E e^{-x}, x = wh dt: exp(r1 dt) + exp(r2 dt).
[[gnu::noinline]] double overdampedA(double omega, double sigma, double dt)
{
    const double wh = std::sqrt(sigma * sigma - omega * omega);
    return std::exp(-dt * omega * omega / (sigma + wh)) + std::exp(-dt * (sigma + wh));
}

// The motion A e^{r1 t} + B e^{r2 t} from q0 and v0.
[[gnu::noinline]] double overdampedMotion(double q0, double v0, double omega, double sigma, double t)
{
    const double wh = std::sqrt(sigma * sigma - omega * omega);
    const double r1 = -omega * omega / (sigma + wh), r2 = -(sigma + wh);
    return (v0 - r2 * q0) / (2.0 * wh) * std::exp(r1 * t) + (r1 * q0 - v0) / (2.0 * wh) * std::exp(r2 * t);
}
}  // namespace

ExactModeCoefficients exactCoefficients(double omega, double sigma, double dt)
{
    ExactModeCoefficients c;
    const double E = std::exp(-sigma * dt);
    c.e = E * E;
    c.a = 2.0 * E * propagator(omega, sigma, dt).C;
    if (beyondCosh(omega, sigma, dt))
        c.a = overdampedA(omega, sigma, dt);
    c.kineticWeight = 0.5 * (1.0 + c.e);
    c.potentialWeight = onePlusEMinusA(omega, sigma, dt) / (dt * dt);
    c.lossWeight = -std::expm1(-2.0 * sigma * dt);
    return c;
}

double staticForcingGain(double omega, double sigma, double dt)
{
    const double x = omega * dt;
    return x == 0.0 ? 1.0 : onePlusEMinusA(omega, sigma, dt) / (x * x);
}

double freeDampedMotion(double q0, double v0, double omega, double sigma, double t)
{
    if (beyondCosh(omega, sigma, t))
        return overdampedMotion(q0, v0, omega, sigma, t);
    const auto [C, S] = propagator(omega, sigma, t);
    return std::exp(-sigma * t) * (q0 * C + (v0 + sigma * q0) * S);
}

}  // namespace jawari
