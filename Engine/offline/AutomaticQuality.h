#pragma once
// The automatic choice of M and R for a scene (docs/design.md section 5): model no more than the
// scene needs. OFF.

#include "offline/Scene.h"
#include "realtime/voice/Quality.h"

namespace jawari
{

// How far the scene's string can ever move at x (m): with the energy-conserving contact the energy
// never rises above the pluck's, H0 = T A^2 L / (2 x_e (L - x_e)), and |u(x)|^2 <= 2 H0 G(x) with
// G(x) = x (L - x) / (T L) the static compliance at x (Cauchy-Schwarz over the modes), so
//   |u(x)| <= A sqrt(x (L - x) / (x_e (L - x_e))).
// Returned with a 25 % margin for the bending stiffness (which adds (1 + B p^2) to each mode's
// energy and takes it from its compliance: a few percent for the strings here).
double reachAt(const Scene& scene, double x);

// Whether some contact point of an obstacle can be reached: g(x) + reach(x) > 0 somewhere on it
// (heights are g, the string at rest is at 0). Only for the energy-conserving method (the
// others can gain energy); any other method counts every obstacle as reachable.
bool obstacleReachable(const Scene& scene, const Obstacle& obstacle);

// The time constant of an impact on the obstacle (s): the string meets it as a dashpot of
// impedance Z = 2 sqrt(T mu) at about the pluck's kink speed v = c A / min(x_e, L - x_e); the
// obstacle's force w K d^alpha balances Z v at the depth d, where its stiffness is
// k = w K alpha d^(alpha-1), and the contact relaxes over Z / k. The paper's obstacle: ~10 ns (no
// rate resolves it); K = 1e7, alpha = 1: 92 us.
double contactTimeConstant(const Scene& scene, const Obstacle& obstacle);

// The automatic choice: the scene's own modes/rate where given; else, when no obstacle can be
// reached (none, or all beyond the string's reach), the modes below 20 kHz at the host rate (no
// contact, nothing to oversample); otherwise the standard setting's modes (of the bridge table when a
// distributed obstacle can be reached, Quality.h), at the standard rate or lower when the contact is
// soft enough: 16 steps per contact time constant and at least 2.5 x the
// highest kept mode.
VoiceQuality automaticQuality(const Scene& scene);

}  // namespace jawari
