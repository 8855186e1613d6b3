#include "physics/body/LinearStringBank.h"

#include <algorithm>

namespace jawari
{

using LoneSpring = ModalSolver::LoneSpring;
const std::array<LinearStringBank::Field, LinearStringBank::kConstants + 7> LinearStringBank::kFields = {{
    {&LinearStringBank::height_, &LoneSpring::height},
    {&LinearStringBank::stiffness_, &LoneSpring::stiffness},
    {&LinearStringBank::chordSlope_, &LoneSpring::chordSlope},
    {&LinearStringBank::weight_, &LoneSpring::weight},
    {&LinearStringBank::coupling_, &LoneSpring::coupling},
    {&LinearStringBank::stringCoupling_, &LoneSpring::stringCoupling},
    {&LinearStringBank::forceScale_, &LoneSpring::forceScale},
    {&LinearStringBank::kappa_, &LoneSpring::kappa},
    {&LinearStringBank::pushPerSlope_, &LoneSpring::pushPerSlope},
    {&LinearStringBank::forcePerSlope_, &LoneSpring::forcePerSlope},
    {&LinearStringBank::uC_, &LoneSpring::uC},
    {&LinearStringBank::uCPrev_, &LoneSpring::uCPrev},
    {&LinearStringBank::slope_, &LoneSpring::slope},
    {&LinearStringBank::delta_, &LoneSpring::delta},
    {&LinearStringBank::deltaPrev_, &LoneSpring::deltaPrev},
    {&LinearStringBank::spring_, &LoneSpring::springForce},
    {&LinearStringBank::springPrev_, &LoneSpring::springForcePrev},
}};

bool LinearStringBank::take(ModalSolver* const* strings, int count)
{
    if (count > kLanes)
        return false;
    for (int i = 0; i < count; ++i)
        if (!fits(*strings[i]))
            return false;
    modes_ = 0;
    for (int i = 0; i < count; ++i)
        modes_ = std::max(modes_, strings[i]->activeModeCount());
    for (auto* table : {&a_, &e_, &phi_, &q_, &qPrev_})
        for (int p = 0; p < modes_; ++p)
            (*table)[size_t(p)].fill(0.0);  // the lanes and modes beyond the strings' stay at rest
    for (const auto& field : kFields)
        (this->*field.first).fill(0.0);
    uTilde_.fill(0.0);
    count_ = count;
    for (int i = 0; i < count; ++i)
    {
        const ModalSolver::LoneSpring s = strings[i]->takeLoneSpring();
        modesOf_[size_t(i)] = s.modes;
        for (int p = 0; p < s.modes; ++p)
        {
            a_[p][i] = s.a[p];
            e_[p][i] = s.e[p];
            phi_[p][i] = s.phi[p];
            q_[p][i] = s.q[p];
            qPrev_[p][i] = s.qPrev[p];
        }
        for (const auto& [lanes, field] : kFields)
            (this->*lanes)[size_t(i)] = s.*field;
    }
    return true;
}

void LinearStringBank::giveBack(ModalSolver* const* strings)
{
    for (int i = 0; i < count_; ++i)
    {
        std::array<double, kModes> q, qPrev;
        ModalSolver::LoneSpring s;
        s.modes = modesOf_[size_t(i)];
        for (int p = 0; p < s.modes; ++p)
        {
            q[size_t(p)] = q_[p][i];
            qPrev[size_t(p)] = qPrev_[p][i];
        }
        for (size_t f = kConstants; f < kFields.size(); ++f)
            s.*kFields[f].second = (this->*kFields[f].first)[size_t(i)];
        strings[i]->giveLoneSpring(q.data(), qPrev.data(), s);
    }
    count_ = 0;
}

void LinearStringBank::predict()
{
    Lanes u{};
    for (int p = 0; p < modes_; ++p)
    {
#pragma omp simd
        for (int i = 0; i < kLanes; ++i)
        {
            const double next = a_[p][i] * q_[p][i] - e_[p][i] * qPrev_[p][i];
            qPrev_[p][i] = next;
            u[size_t(i)] += phi_[p][i] * next;
        }
    }
    uTilde_ = u;
}

// Each string's slope G at the bridge's (before, move): the root of r + k G(r) = b with the spring's
// affine chord slope G(r) = -K s + d r (ContactLaw's bilateral law), r = (b + k K s) / (1 + k d), as
// solveScalarContact poses it.
void LinearStringBank::springSlopes(double before, double move, Lanes& G) const
{
    Lanes s, r;
#pragma omp simd
    for (int i = 0; i < kLanes; ++i)
    {
        s[size_t(i)] = height_[size_t(i)] + before - uCPrev_[size_t(i)] - deltaPrev_[size_t(i)];
        const double b = uTilde_[size_t(i)] - uCPrev_[size_t(i)] - kappa_[size_t(i)] * deltaPrev_[size_t(i)] - move;
        const double atZero = -stiffness_[size_t(i)] * s[size_t(i)];
        r[size_t(i)] = (b - coupling_[size_t(i)] * atZero) / (1.0 + coupling_[size_t(i)] * chordSlope_[size_t(i)]);
    }
    for (int i = 0; i < count_; ++i)
        G[size_t(i)] = -stiffness_[size_t(i)] * s[size_t(i)] + chordSlope_[size_t(i)] * r[size_t(i)];
}

double LinearStringBank::force(double before, double move, double* slope) const
{
    Lanes G{};
    springSlopes(before, move, G);
    double sum = 0.0, dSum = 0.0;
    for (int i = 0; i < count_; ++i)
    {
        const double d = chordSlope_[size_t(i)];
        sum += weight_[size_t(i)] * G[size_t(i)];
        dSum -= weight_[size_t(i)] * d / (1.0 + coupling_[size_t(i)] * d);  // b falls by one per metre of move
    }
    if (slope != nullptr)
        *slope = dSum;
    return sum;
}

double LinearStringBank::solve(double before, double move)
{
    springSlopes(before, move, slope_);
    double sum = 0.0;
    for (int i = 0; i < count_; ++i)
        sum += weight_[size_t(i)] * slope_[size_t(i)];
    return sum;
}

// u_C^{n+1} = u~ - kString G, the residual compliance's advance, and q^{n+1} = q~ + c phi with
// c = -(dt^2/mu) w G, each string's own.
void LinearStringBank::finish()
{
    Lanes c;
#pragma omp simd
    for (int i = 0; i < kLanes; ++i)
    {
        const double G = slope_[size_t(i)];
        uCPrev_[size_t(i)] = uC_[size_t(i)];
        uC_[size_t(i)] = uTilde_[size_t(i)] - stringCoupling_[size_t(i)] * G;
        const double back = kappa_[size_t(i)] - 1.0;
        const double delta = delta_[size_t(i)], spring = spring_[size_t(i)];
        delta_[size_t(i)] = -back * deltaPrev_[size_t(i)] - pushPerSlope_[size_t(i)] * G;
        spring_[size_t(i)] = -back * springPrev_[size_t(i)] - forcePerSlope_[size_t(i)] * G;
        deltaPrev_[size_t(i)] = delta;
        springPrev_[size_t(i)] = spring;
        c[size_t(i)] = -forceScale_[size_t(i)] * weight_[size_t(i)] * G;
    }
    for (int p = 0; p < modes_; ++p)
    {
#pragma omp simd
        for (int i = 0; i < kLanes; ++i)
        {
            const double next = qPrev_[p][i] + c[size_t(i)] * phi_[p][i];
            qPrev_[p][i] = q_[p][i];
            q_[p][i] = next;
        }
    }
}

void LinearStringBank::silence()
{
    for (auto* table : {&q_, &qPrev_})
        for (auto& row : *table)
            row.fill(0.0);
    for (size_t f = kConstants; f < kFields.size(); ++f)
        (this->*kFields[f].first).fill(0.0);
    uTilde_.fill(0.0);
}

}  // namespace jawari
