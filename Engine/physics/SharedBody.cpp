#include "physics/SharedBody.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace jawari
{

SharedBody::SharedBody(const ModalBody& body, double coupling, double timeStep)
    : coupling_(coupling)
    , dt_(timeStep)
{
    validateBody(body);
    if (!(std::isfinite(coupling) && coupling >= 0.0) || !(timeStep > 0.0))
        throw std::invalid_argument("a shared body needs a finite coupling >= 0 and a time step > 0");
    double inverseMass = 0.0;
    for (const auto& mode : body.modes)
    {
        const double w = 2.0 * std::numbers::pi * mode.frequencyHz;
        coefficients_.push_back(exactCoefficients(w, mode.sigma, dt_));
        push_.push_back(dt_ * dt_ * coupling / mode.massKg);
        radiation_.push_back(mode.radiation);
        inverseMass += 1.0 / mode.massKg;
    }
    beta_ = dt_ * dt_ * coupling * coupling * inverseMass;
    z_.assign(body.modes.size(), 0.0);
    zPrevious_ = z_;
    zNext_ = z_;
}

void SharedBody::check(const ModalSolver& string) const
{
    if (string.timeStep() != dt_)
        throw std::invalid_argument("a shared body's strings step at its time step");
    if (string.contactCount() > 0
        && (string.contactMethod() != ContactMethod::energyConserving || string.leavesOutOfReach()))
        throw std::invalid_argument("a shared body's strings solve their contacts by the energy-conserving method, "
                                    "every point kept live");
}

double SharedBody::bridgeDisplacement() const
{
    double w = 0.0;
    for (double z : z_)
        w += z;
    return coupling_ * w;
}

double SharedBody::radiation() const
{
    double p = 0.0;
    for (size_t k = 0; k < z_.size(); ++k)
        p += radiation_[k] * z_[k];
    return p;
}

bool SharedBody::atRest() const
{
    return std::all_of(z_.begin(), z_.end(), [](double z) { return std::abs(z) < 1e-18; })
           && std::all_of(zPrevious_.begin(), zPrevious_.end(), [](double z) { return std::abs(z) < 1e-18; });
}

void SharedBody::silence()
{
    std::fill(z_.begin(), z_.end(), 0.0);
    std::fill(zPrevious_.begin(), zPrevious_.end(), 0.0);
    force_ = 0.0;
}

// The residual of W = w~ + beta F(W) at one W: every string's contact solved with the bridge there.
double SharedBody::evaluate(ModalSolver* const* strings, int count, double before, double bridge)
{
    ++evaluations_;
    force_ = 0.0;
    for (int i = 0; i < count; ++i)
        force_ += strings[i]->solveOnMovingBridge(before, bridge - before);
    return force_;
}

void SharedBody::step(ModalSolver* const* strings, int count)
{
    double before = 0.0, predicted = 0.0;
    for (size_t k = 0; k < z_.size(); ++k)
    {
        zNext_[k] = coefficients_[k].a * z_[k] - coefficients_[k].e * zPrevious_[k];
        before += zPrevious_[k];
        predicted += zNext_[k];
    }
    before *= coupling_;
    predicted *= coupling_;
    for (int i = 0; i < count; ++i)
        strings[i]->predictOnMovingBridge();
    evaluations_ = 0;
    // Secant on R(W) = W - w~ - beta F(W), from the bridge with last step's force and the fixed
    // point's step after it. Stops when the bridge moves by less than rounding's share of it.
    double w0 = predicted + beta_ * force_;
    double r0 = w0 - predicted - beta_ * evaluate(strings, count, before, w0);
    if (r0 != 0.0)
    {
        double w1 = w0 - r0;
        constexpr int kMostEvaluations = 16;
        while (evaluations_ < kMostEvaluations)
        {
            const double r1 = w1 - predicted - beta_ * evaluate(strings, count, before, w1);
            const double tolerance = 1e-14 * (std::abs(w1) + std::abs(predicted - before)) + 1e-30;
            if (std::abs(r1) <= tolerance || r1 == r0)
                break;
            const double next = w1 - r1 * (w1 - w0) / (r1 - r0);
            w0 = w1;
            r0 = r1;
            w1 = next;
        }
    }
    for (int i = 0; i < count; ++i)
        strings[i]->finishOnMovingBridge();
    for (size_t k = 0; k < z_.size(); ++k)
    {
        zPrevious_[k] = z_[k];
        z_[k] = zNext_[k] + push_[k] * force_;
    }
}

}  // namespace jawari
