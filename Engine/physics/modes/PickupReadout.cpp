#include "physics/modes/PickupReadout.h"

#include "physics/modes/ModalKernels.h"
#include "physics/modes/ModalState.h"

#include <algorithm>

namespace jawari
{

namespace
{
// The share of a mode of frequency omega read as it moves: 1 up to the band, 0 from 1.25 times it,
// linear in the frequency between.
double movingShare(double omega, double bandOmega)
{
    if (bandOmega == 0.0)
        return 1.0;
    return std::clamp((1.25 * bandOmega - omega) / (0.25 * bandOmega), 0.0, 1.0);
}
}  // namespace

void PickupReadout::configure(const std::vector<double>& weights, int modes, double bandOmega, int points)
{
    base_ = weights;
    if (!base_.empty())
        base_.edit().resize(size_t(modes), 0.0);
    bandOmega_ = bandOmega;
    weights_.edit().resize(base_.size());
    if (bandOmega_ > 0.0)
        static_.edit().resize(base_.size());
    atPoint_.assign(size_t(points), 0.0);
}

void PickupReadout::setWeights(const std::vector<double>& omega, double scale)
{
    scale_ = scale;
    if (!present())
        return;
    auto& weights = weights_.edit();
    auto& statics = static_.edit();
    for (size_t p = 0; p < base_.size(); ++p)
    {
        const double moving = movingShare(omega[p], bandOmega_);
        const double kept = scale * moving;
        weights[p] = kept * base_[p];
        if (!statics.empty())
            statics[p] = (1.0 - moving) * scale * base_[p];
    }
}

void PickupReadout::scaleConfigured(const double* ratio)
{
    if (!present())
        return;
    auto& base = base_.edit();
    kernels::scaleEach(ratio, base.data(), int(base.size()));
}

// Point j's response sums h_p phi_p(x_j) mode by mode; the excitation's by kernels::dot.
void PickupReadout::readForces(const Forces& forces)
{
    if (!present())
        return;
    const size_t M = weights_.size();
    for (size_t j = 0; j < forces.contacts.size(); ++j)
    {
        const double* shape = forces.contactShapes.data() + j * M;
        double h = 0.0;
        for (size_t p = 0; p < M; ++p)
            h += weights_[p] * shape[p];
        atPoint_[j] = forces.forceScale * forces.contacts[j].weight * (h + staticResponse(shape, forces.coefficients));
    }
    const auto& excitation = forces.excitationShape;
    if (!excitation.empty())
        atExcitation_ = forces.forceScale
                        * (kernels::dot(weights_.data(), excitation.data(), static_cast<int>(M))
                           + staticResponse(excitation.data(), forces.coefficients));
}

void PickupReadout::rereadActive(const double* h, const ModalState& state, const Forces& forces, bool atPoints)
{
    const int Ma = state.activeCount();
    const size_t M = base_.size();
    for (size_t j = 0; j < forces.contacts.size() && atPoints; ++j)
        atPoint_[j] = forces.forceScale * forces.contacts[j].weight
                      * (kernels::dot(h, state.phi(static_cast<int>(j)), Ma)
                         + staticResponse(forces.contactShapes.data() + j * M, forces.coefficients));
    if (!forces.excitationShape.empty())
        atExcitation_ =
            forces.forceScale
            * (kernels::dot(h, state.phiE(), Ma) + staticResponse(forces.excitationShape.data(), forces.coefficients));
    read(h, state);
}

void PickupReadout::read(const double* h, const ModalState& state)
{
    value = h != nullptr ? kernels::dot(h, state.q(), state.activeCount()) : 0.0;
}

double PickupReadout::staticResponse(const double* shape, const std::vector<ExactModeCoefficients>& coefficients) const
{
    double sum = 0.0;
    for (size_t p = 0; p < static_.size(); ++p)
        if (static_[p] != 0.0)
            sum += static_[p] * shape[p] / (1.0 - coefficients[p].a + coefficients[p].e);
    return sum;
}

double PickupReadout::aboveBand(const ModalState& state) const
{
    double sum = 0.0;
    for (int p = 0; p < static_cast<int>(static_.size()); ++p)
        if (const int i = state.indexOfMode(p); i >= 0 && static_[size_t(p)] != 0.0)
            sum += static_[size_t(p)] * state.mode(i).now;
    return sum;
}

double PickupReadout::compliance(double mu, const std::vector<double>& omega) const
{
    double sum = 0.0;
    for (size_t p = 0; p < base_.size(); ++p)
    {
        const double h = scale_ * base_[p];
        sum += h * h / (mu * omega[p] * omega[p]);
    }
    return sum;
}

}  // namespace jawari
