#include "physics/contact/PenaltyContact.h"

#include <cmath>

namespace jawari
{

int PenaltyContact::solve(const std::vector<ContactPoint>& contacts, const double* penetration, double* slope)
{
    for (size_t j = 0; j < contacts.size(); ++j)
        slope[j] = contacts[j].law.bilateral ? -contacts[j].law.stiffness * penetration[j]  // its damper dropped
                   : penetration[j] > 0.0
                       ? -contacts[j].law.stiffness * std::pow(penetration[j], contacts[j].law.exponent)
                       : 0.0;
    return 0;
}

}  // namespace jawari
