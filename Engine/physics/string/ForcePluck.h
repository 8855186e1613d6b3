#pragma once
// The force pluck of van Walstijn, Bridges & Mehes (DAFx-16, eqs. 14-15 and 19-20): a finger's push
// that starts the string from rest, so that it meets its bridge and thread in their rest state,
//
//   F(t) = a sin^2[(pi / tau) h(t - t0)]  for t0 <= t <= t0 + tau, 0 elsewhere,
//   h(t) = [t + tau sinh(beta t / tau) / sinh(beta)] / 2,
//
// which rises slowly and lets go abruptly (beta sets how abruptly), spread along the string over
// [x - w/2, x + w/2] by psi(x') = (pi / 2w) cos(pi (x' - x) / w), a unit integral.

#include <vector>

namespace jawari
{

struct ForcePluck
{
    double position = 0.5;   // x (m), the centre of the push
    double width = 1.0;      // w (m); the whole of a 1 m string by default, as DAFx-16's
    double amplitude = -0.4; // a (N); < 0 pushes towards the obstacles
    double duration = 0.05;  // tau (s)
    double steepness = 30.0; // beta (none), > 0
    double start = 0.0;      // t0 (s)
};

// F(t) in newtons. RT.
double forcePluckNewtons(const ForcePluck& pluck, double t);

// The push's shape over the sine modes phi_p(x) = sqrt(2/L) sin(p pi x / L), p = 1..M:
// g_p = int psi phi_p dx = phi_p(x) pi^2 cos(k w / 2) / (pi^2 - k^2 w^2), k = p pi / L (pi/4 phi_p(x)
// where k w = pi). A width of 0 is a point force, g_p = phi_p(x). OFF.
std::vector<double> forcePluckModalShape(double lengthMetres, int modeCount, const ForcePluck& pluck);

}  // namespace jawari
