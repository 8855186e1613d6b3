#include "physics/SharedBody.h"

#include "physics/ModalKernels.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <utility>

namespace jawari
{

SharedBody::SharedBody(const ModalBody& body, double coupling, double timeStep)
    : dt_(timeStep)
{
    validateBody(body);
    if (!(std::isfinite(coupling) && coupling >= 0.0) || !(timeStep > 0.0))
        throw std::invalid_argument("a shared body needs a finite coupling >= 0 and a time step > 0");
    double inverseMass = 0.0;
    for (const auto& mode : body.modes)
    {
        const auto c = exactCoefficients(2.0 * std::numbers::pi * mode.frequencyHz, mode.sigma, dt_);
        a_.push_back(c.a);
        e_.push_back(c.e);
        push_.push_back(dt_ * dt_ * coupling / mode.massKg);
        kappa_.push_back(coupling);
        weights_.push_back(mode.radiation);
        radiationPush_ += mode.radiation * push_.back();
        inverseMass += 1.0 / mode.massKg;
    }
    beta_ = dt_ * dt_ * coupling * coupling * inverseMass;
    z_.assign(body.modes.size(), 0.0);
    zPrevious_ = zPart_ = zPartPrevious_ = z_;
}

void SharedBody::check(const ModalSolver& string) const
{
    if (string.timeStep() != dt_)
        throw std::invalid_argument("a shared body's strings step at its time step");
    const auto method = string.contactMethod();
    if (string.contactCount() > 0
        && ((method != ContactMethod::energyConserving && method != ContactMethod::quadraticSpline)
            || string.leavesOutOfReach()))
        throw std::invalid_argument("a shared body's strings solve their contacts by the energy-conserving method "
                                    "or the quadratic spline, every point kept live");
}

void SharedBody::checkLinear(const ModalSolver& string) const
{
    check(string);
    for (int j = 0; j < string.contactCount(); ++j)
        if (!string.contact(j).law.bilateral)
            throw std::invalid_argument("a shared body's linear strings touch it through springs (bilateral points) only");
}

bool SharedBody::atRest() const
{
    auto still = [](const std::vector<double>& z) {
        return std::all_of(z.begin(), z.end(), [](double x) { return std::abs(x) < 1e-18; });
    };
    return still(z_) && still(zPrevious_) && still(zPart_) && still(zPartPrevious_);
}

void SharedBody::silence()
{
    for (auto* z : {&z_, &zPrevious_, &zPart_, &zPartPrevious_})
        std::fill(z->begin(), z->end(), 0.0);
    force_ = bridge_ = bridgeBefore_ = radiation_ = partRadiation_ = playedForce_ = 0.0;
}

// The force at one W: the strings before split solved with the bridge there, the linear ones
// after it from their affine fit (fitLinear).
double SharedBody::evaluate(ModalSolver* const* strings, double before, double bridge)
{
    ++evaluations_;
    playedForce_ = 0.0;
    for (int i = 0; i < split_; ++i)
        playedForce_ += strings[i]->solveOnMovingBridge(before, bridge - before);
    if (split_ == count_)
        return playedForce_;
    return playedForce_ + linearForce_ + linearSlope_ * (bridge - linearAt_);
}

// The linear strings' force with the bridge at W, each solved there (and keeping that solve).
double SharedBody::solveLinear(ModalSolver* const* strings, double before, double bridge)
{
    double force = 0.0;
    for (int i = split_; i < count_; ++i)
        force += strings[i]->solveOnMovingBridge(before, bridge - before);
    return force;
}

// Every point of a linear string is a spring, so its force is affine in W: measured at two
// displacements, it needs no solve per secant evaluation.
void SharedBody::fitLinear(ModalSolver* const* strings, double before, double at)
{
    constexpr double kStep = 1e-9;  // m: any step measures an affine force; this one keeps rounding small
    linearAt_ = at;
    linearForce_ = solveLinear(strings, before, at);
    linearSlope_ = (solveLinear(strings, before, at + kStep) - linearForce_) / kStep;
}

// W^{n+1}: the secant on R(W) = W - w~ - beta F(W), from the W that solves it with the played
// strings' force as the last step left it (and the linear strings' affine force), and the last
// step's slope R'. Stops when the residual is rounding's share of the bridge's motion; the played
// strings keep the solve of the last W, and playedForce_ is theirs.
double SharedBody::solveBridge(ModalSolver* const* strings, double before, double predicted)
{
    auto tolerance = [&](double w) { return 1e-14 * (std::abs(w) + std::abs(predicted - before)) + 1e-30; };
    if (split_ < count_)
        fitLinear(strings, before, predicted + beta_ * force_);
    double w0 = (predicted + beta_ * (playedForce_ + linearForce_ - linearSlope_ * linearAt_)) / (1.0 - beta_ * linearSlope_);
    double r0 = w0 - predicted - beta_ * evaluate(strings, before, w0);
    if (r0 == 0.0 || (split_ < count_ && std::abs(r0) <= tolerance(w0)))
        return w0;
    double w1 = w0 - r0 / slope_;
    constexpr int kMostEvaluations = 16;
    while (true)
    {
        const double r1 = w1 - predicted - beta_ * evaluate(strings, before, w1);
        if (std::abs(r1) <= tolerance(w1) || r1 == r0 || evaluations_ >= kMostEvaluations)
            return w1;
        const double slope = (r1 - r0) / (w1 - w0);
        if (std::isfinite(slope) && slope > 0.5)  // R' = 1 + beta F' >= 1 where F is monotone
            slope_ = slope;
        w0 = w1;
        r0 = r1;
        w1 -= r1 / slope_;
    }
}

// The copy of the modes that the strings after split drive: the same update, their force alone.
void SharedBody::stepPart(double partForce)
{
    double unused = 0.0;
    const int K = static_cast<int>(zPart_.size());
    const double radiated =
        kernels::predict(a_.data(), e_.data(), zPart_.data(), zPartPrevious_.data(), weights_.data(), nullptr, K, K, unused);
    kernels::axpy(partForce, push_.data(), zPartPrevious_.data(), K);
    std::swap(zPart_, zPartPrevious_);
    partRadiation_ = radiated + radiationPush_ * partForce;
}

void SharedBody::step(ModalSolver* const* strings, int count, int split)
{
    // z~ over z^{n-1}, with its bridge reading and its radiation's, in one pass.
    double radiated = 0.0;
    const int K = static_cast<int>(z_.size());
    const double predicted = kernels::predict(a_.data(), e_.data(), z_.data(), zPrevious_.data(), kappa_.data(),
                                              weights_.data(), K, K, radiated);
    for (int i = 0; i < count; ++i)
        strings[i]->predictOnMovingBridge();
    evaluations_ = 0;
    split_ = split;
    count_ = count;
    // One way, the strings' bridge stands still: their solve once, with it at rest.
    const double before = oneWay_ ? 0.0 : bridgeBefore_;
    const double bridge = oneWay_ ? 0.0 : solveBridge(strings, before, predicted);
    if (oneWay_)
        evaluate(strings, 0.0, 0.0);
    force_ = playedForce_;
    if (split < count)
    {
        partForce_ = solveLinear(strings, before, bridge);
        force_ += partForce_;
    }
    for (int i = 0; i < count; ++i)
        strings[i]->finishOnMovingBridge();
    if (split < count)
        stepPart(partForce_);
    kernels::axpy(force_, push_.data(), zPrevious_.data(), K);
    std::swap(z_, zPrevious_);
    bridgeBefore_ = bridge_;
    bridge_ = predicted + beta_ * force_;
    radiation_ = radiated + radiationPush_ * force_;
}

}  // namespace jawari
