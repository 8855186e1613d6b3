#include "physics/SharedBody.h"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace jawari
{

SharedBody::SharedBody(const ModalBody& body, double coupling, const std::vector<ModalSolver*>& strings)
    : coupling_(coupling)
{
    validateBody(body);
    if (strings.empty())
        throw std::invalid_argument("a shared body needs strings");
    dt_ = strings.front()->timeStep();
    double inverseMass = 0.0;
    for (const auto& mode : body.modes)
    {
        coefficients_.push_back(exactCoefficients(2.0 * std::numbers::pi * mode.frequencyHz, mode.sigma, dt_));
        push_.push_back(dt_ * dt_ * coupling / mode.massKg);
        inverseMass += 1.0 / mode.massKg;
    }
    z_.assign(body.modes.size(), 0.0);
    zPrevious_ = z_;
    zNext_ = z_;
    const double beta = dt_ * dt_ * coupling * coupling * inverseMass;
    const auto n = Eigen::Index(strings.size());
    Eigen::MatrixXd A(n, n);
    std::vector<ContactPoint> points;
    for (Eigen::Index i = 0; i < n; ++i)
    {
        const ModalSolver& s = *strings[size_t(i)];
        if (s.contactCount() != 1 || s.timeStep() != dt_)
            throw std::invalid_argument("a shared body's strings have one contact point each, at one time step");
        points.push_back(s.contact(0));
        weight_.push_back(s.contact(0).weight);
    }
    for (Eigen::Index i = 0; i < n; ++i)
        for (Eigen::Index j = 0; j < n; ++j)
            A(i, j) = beta * weight_[size_t(j)] + (i == j ? strings[size_t(i)]->contactSelfCoupling(0) : 0.0);
    system_.prepare(points, A);
    requests_.resize(size_t(n));
    for (auto* v : {&s_, &b_, &r_, &slope_})
        v->assign(size_t(n), 0.0);
}

double SharedBody::bridgeDisplacement() const
{
    double w = 0.0;
    for (double z : z_)
        w += z;
    return coupling_ * w;
}

bool SharedBody::step(ModalSolver* const* strings, int count)
{
    for (int i = 0; i < count; ++i)
        if (!strings[i]->nextStepWaits())
            return false;
    // The body's prediction, and the bridge's w^{n-1} and predicted w~.
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
    {
        strings[i]->beginStep(requests_[size_t(i)]);  // waits (checked above)
        s_[size_t(i)] = requests_[size_t(i)].s + before;
        b_[size_t(i)] = requests_[size_t(i)].b - (predicted - before);
    }
    const int iterations = system_.solve(s_.data(), b_.data(), r_.data(), slope_.data());
    force_ = 0.0;
    for (int i = 0; i < count; ++i)
    {
        ScalarContactSolution solution;
        solution.r = r_[size_t(i)];
        solution.slope = slope_[size_t(i)];
        solution.iterations = iterations;
        strings[i]->finishStep(solution);
        force_ += weight_[size_t(i)] * slope_[size_t(i)];
    }
    for (size_t k = 0; k < z_.size(); ++k)
    {
        zPrevious_[k] = z_[k];
        z_[k] = zNext_[k] + push_[k] * force_;
    }
    return true;
}

}  // namespace jawari
