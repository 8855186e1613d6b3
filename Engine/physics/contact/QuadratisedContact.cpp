#include "physics/contact/QuadratisedContact.h"

#include "physics/contact/ContactLaw.h"

#include <algorithm>
#include <cmath>

namespace jawari
{

void QuadratisedContact::prepare(int points)
{
    gradient_.assign(points, 0.0);
    response_.assign(points, 0.0);
}

void QuadratisedContact::restart(const std::vector<ContactPoint>& contacts, const double* u, const double* uPrev)
{
    xi_ = xiPrev_ = 0.0;
    for (size_t j = 0; j < contacts.size(); ++j)
    {
        xi_ += contacts[j].weight * contactPotential(contacts[j].law, contacts[j].height - u[j]);
        xiPrev_ += contacts[j].weight * contactPotential(contacts[j].law, contacts[j].height - uPrev[j]);
    }
    xi_ = std::sqrt(2.0 * xi_);
    xiPrev_ = std::sqrt(2.0 * xiPrev_);
}

void QuadratisedContact::reset()
{
    xi_ = xiPrev_ = 0.0;
}

int QuadratisedContact::solve(const std::vector<ContactPoint>& contacts, const double* penetration, const double* b,
                              const Eigen::MatrixXd& pointCoupling, double* slope)
{
    const int P = static_cast<int>(contacts.size());
    double V = 0.0;
    bool touching = false;
    for (int j = 0; j < P; ++j)
    {
        const auto& law = contacts[j].law;
        if (law.bilateral)  // the spring on both sides; its damper dropped
        {
            touching = true;
            V += contacts[j].weight * contactPotential(law, penetration[j]);
            gradient_[j] = -contacts[j].weight * law.stiffness * penetration[j];
        }
        else if (penetration[j] > 0.0)
        {
            touching = true;
            V += contacts[j].weight * contactPotential(law, penetration[j]);
            gradient_[j] = -contacts[j].weight * law.stiffness * std::pow(penetration[j], law.exponent);
        }
        else
            gradient_[j] = 0.0;
    }
    if (!touching || V <= 0.0)
    {
        // Out of contact V = 0, so xi = sqrt(2 V) = 0: what the recursion xi^{n+1} = xi^{n-1}
        // would carry over is drift, released here (it can only lower the energy) instead of
        // pushing with a stale force at the next contact.
        std::fill(slope, slope + P, 0.0);
        xiPrev_ = xi_;
        xi_ = 0.0;
        return 0;
    }
    const double root = std::sqrt(2.0 * V);
    double gDotB = 0.0, gDotV = 0.0;
    for (int j = 0; j < P; ++j)
        gradient_[j] /= root;
    for (int i = 0; i < P; ++i)
    {
        double v = 0.0;
        for (int j = 0; j < P; ++j)
            v += pointCoupling(i, j) * gradient_[j];
        response_[i] = v;  // B g
    }
    for (int j = 0; j < P; ++j)
    {
        gDotB += gradient_[j] * (b[j] - response_[j] * xiPrev_);
        gDotV += gradient_[j] * response_[j];
    }
    const double gDotR = gDotB / (1.0 + 0.5 * gDotV);  // g . R from Sherman-Morrison
    const double mean = xiPrev_ + 0.5 * gDotR;         // (xi^{n+1} + xi^{n-1}) / 2
    for (int j = 0; j < P; ++j)
        slope[j] = gradient_[j] * mean / contacts[j].weight;  // f = F / w = -g mean / w; G = -f
    const double xiNext = xiPrev_ + gDotR;
    xiPrev_ = xi_;
    xi_ = xiNext;
    return 0;
}

}  // namespace jawari
