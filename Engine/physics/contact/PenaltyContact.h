#pragma once
// The explicit penalty contact (docs/design.md section 4): the force at u^n, f^n = K [g - u^n]_+^alpha,
// with no solve. Cheap, and unstable once K dt^2 / mu is large (the stability map charts where). A
// bilateral law (ContactLaw.h) gives its spring's K (g - u^n) and drops its damper.

#include "physics/contact/Obstacle.h"

#include <vector>

namespace jawari
{

struct PenaltyContact
{
    // RT: the slopes G_j = -f_j of the step (f: force per metre of string, > 0 pushes the string up)
    // from each point's penetration at n. Returns 0 iterations.
    static int solve(const std::vector<ContactPoint>& contacts, const double* penetration, double* slope);
};

}  // namespace jawari
