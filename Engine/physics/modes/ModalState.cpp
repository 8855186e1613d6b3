#include "physics/modes/ModalState.h"

#include "physics/modes/ModalKernels.h"
#include "physics/modes/StampedVector.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iterator>

namespace jawari
{

void ModalState::compact(const std::vector<char>& coupled, const std::vector<double>& current,
                         const std::vector<double>& previous, const std::vector<double>& excitationShape,
                         const std::vector<double>& contactShapes, int contactCount, bool exactSize, bool pairable)
{
    M_ = static_cast<int>(current.size());
    contactCount_ = contactShapes.empty() ? 0 : contactCount;
    pairable_ = pairable;
    double largest = 0.0;
    for (int p = 0; p < M_; ++p)
        largest = std::max({largest, std::abs(current[p]), std::abs(previous[p])});
    const double stateFloor = 1e-13 * largest;
    active_.clear();
    for (int p = 0; p < M_; ++p)
        if (coupled[p] || std::abs(current[p]) > stateFloor || std::abs(previous[p]) > stateFloor)
            active_.push_back(p);
    Ma_ = static_cast<int>(active_.size());
    // Padding to whole blocks keeps the kernels off their scalar tail loops (a = e = h = phi = 0).
    Mpad_ = exactSize ? Ma_ : (Ma_ + kernels::kBlock - 1) / kernels::kBlock * kernels::kBlock;
    pickupCount_ = Mpad_;  // until fillTables() has the weights
    activeNormal_.resize(Ma_);
    activeReleased_.resize(Ma_);
    indexOfMode_.assign(M_, -1);
    // stride_ * 8 bytes = 576 (mod 4096): consecutive arrays sit 9 cache lines apart modulo 4 KiB.
    stride_ = (Mpad_ + 7) / 8 * 8;
    while ((stride_ * 8) % 4096 != 576)
        stride_ += 8;
    const int arrays = 10 + contactCount_;
    storage_.assign(static_cast<size_t>(stride_) * arrays + 8, 0.0);
    double* next = alignedBase();
    for (double** array : {&aNormal_, &eNormal_, &aReleased_, &eReleased_, &h_, &q_, &qPrev_, &settled_, &phiE_, &h2_})
    {
        *array = next;
        next += stride_;
    }
    phi_ = contactCount_ > 0 ? next : nullptr;
    for (int i = 0; i < Ma_; ++i)
    {
        const int p = active_[i];
        indexOfMode_[p] = i;
        q_[i] = current[p];
        qPrev_[i] = previous[p];
        phiE_[i] = excitationShape.empty() ? 0.0 : excitationShape[p];
    }
    released_ = false;
    a_ = aNormal_;
    e_ = eNormal_;
    tablesStamp_ = detail::nextTableStamp();
    for (int j = 0; j < contactCount_; ++j)
        for (int i = 0; i < Ma_; ++i)
            phi_[size_t(j) * stride_ + i] = contactShapes[size_t(j) * M_ + active_[i]];
    layout_ = Layout::single;
    c1_ = c2_ = 0.0;
}

void ModalState::rescaleModes(const double* ratio)
{
    tablesStamp_ = detail::nextTableStamp();
    for (int i = 0; i < Ma_; ++i)
    {
        const double r = ratio[active_[i]];
        q_[i] /= r;
        qPrev_[i] /= r;
        phiE_[i] *= r;
        for (int j = 0; j < contactCount_; ++j)
            phi_[size_t(j) * stride_ + i] *= r;
    }
}

ModalState& ModalState::operator=(const ModalState& other)
{
    if (this == &other)
        return *this;
    const bool sameTables = tablesStamp_ != 0 && tablesStamp_ == other.tablesStamp_
                            && storage_.size() == other.storage_.size();
    static_cast<ModalStateScalars&>(*this) = other;
    if (!sameTables)
        static_cast<ModalStateTables&>(*this) = other;
    copyArraysFrom(other, sameTables);
    return *this;
}

namespace
{
// The first 64-byte-aligned double at or after p.
template <typename Double>
Double* aligned64(Double* p)
{
    while (reinterpret_cast<std::uintptr_t>(p) % 64 != 0)
        ++p;
    return p;
}
}  // namespace

double* ModalState::alignedBase()
{
    return aligned64(storage_.data());
}

// The two states' storage may sit differently against 64 bytes, so the arrays are copied from
// aligned base to aligned base, and each pointer keeps its offset from the base (q_ and qPrev_
// trade places as the steps go, a_ and e_ point at either damping set). The state arrays q, qPrev
// and settled are three consecutive strides (compact()), whichever of them q_ and qPrev_ are.
void ModalState::copyArraysFrom(const ModalState& other, bool stateOnly)
{
    if (storage_.size() != other.storage_.size())
        storage_.assign(other.storage_.size(), 0.0);
    if (other.storage_.empty())
        return;
    const double* from = aligned64(other.storage_.data());
    double* to = alignedBase();
    if (stateOnly)
    {
        const size_t first = size_t(std::min({other.q_, other.qPrev_, other.settled_}) - from);
        std::copy(from + first, from + first + 3 * size_t(stride_), to + first);
    }
    else
        std::copy(from, from + (other.storage_.size() - 8), to);
    static constexpr double* ModalStateArrays::*kArrays[] = {
        &ModalStateArrays::a_,       &ModalStateArrays::e_,         &ModalStateArrays::aNormal_,
        &ModalStateArrays::eNormal_, &ModalStateArrays::aReleased_, &ModalStateArrays::eReleased_,
        &ModalStateArrays::h_,       &ModalStateArrays::h2_,        &ModalStateArrays::phiE_,
        &ModalStateArrays::phi_,     &ModalStateArrays::q_,         &ModalStateArrays::qPrev_,
        &ModalStateArrays::settled_};
    static_assert(sizeof(ModalStateArrays) == std::size(kArrays) * sizeof(double*),
                  "every pointer of ModalStateArrays is rebased here");
    ModalStateArrays& mine = *this;
    const ModalStateArrays& theirs = other;
    for (double* ModalStateArrays::*array : kArrays)
        mine.*array = theirs.*array == nullptr ? nullptr : to + (theirs.*array - from);
}

void ModalState::fillTables(const std::vector<ExactModeCoefficients>& normal,
                            const std::vector<ExactModeCoefficients>& released,
                            const std::vector<double>& pickupWeights,
                            const std::vector<double>& secondPickupWeights)
{
    tablesStamp_ = detail::nextTableStamp();
    hasSecondPickup_ = !secondPickupWeights.empty();
    for (int i = 0; i < Ma_; ++i)
    {
        const int p = active_[i];
        activeNormal_[i] = normal[p];
        activeReleased_[i] = released[p];
        aNormal_[i] = normal[p].a;
        eNormal_[i] = normal[p].e;
        aReleased_[i] = released[p].a;
        eReleased_[i] = released[p].e;
        h_[i] = pickupWeights[p];
        h2_[i] = hasSecondPickup_ ? secondPickupWeights[p] : 0.0;
    }
    int read = Ma_;
    while (read > 0 && h_[read - 1] == 0.0 && h2_[read - 1] == 0.0)
        --read;
    pickupCount_ = Mpad_ == Ma_ ? Ma_ : std::min(Mpad_, (read + kernels::kBlock - 1) / kernels::kBlock * kernels::kBlock);
    for (int set = 0; set < 2; ++set)
    {
        const double* a = set == 0 ? aNormal_ : aReleased_;
        const double* e = set == 0 ? eNormal_ : eReleased_;
        steepFrom_[set] = int(std::find_if(e, e + Ma_, [](double x) { return x < 1e-2; }) - e);
        sumAPhiSquared_[set] = sumAPhiH_[set] = sumAPhiH2_[set] = 0.0;
        if (pairable_ && contactCount_ == 1)
            for (int i = 0; i < Ma_; ++i)
            {
                sumAPhiSquared_[set] += a[i] * phi_[i] * phi_[i];
                sumAPhiH_[set] += a[i] * phi_[i] * h_[i];
                sumAPhiH2_[set] += a[i] * phi_[i] * h2_[i];
            }
    }
}

ModalState::Mode ModalState::mode(int i) const
{
    const double* phi = singlePhi();
    const double ph = phi != nullptr ? phi[i] : 0.0;
    switch (layout_)
    {
        case Layout::single: break;
        case Layout::pairBoundary: return {q_[i] + (c1_ * a_[i] + c2_) * ph, qPrev_[i] + c1_ * ph};
        case Layout::pairMiddle: return {qPrev_[i] + c1_ * ph, settled_[i]};
    }
    return {q_[i], qPrev_[i]};
}

void ModalState::toSingle()
{
    if (layout_ == Layout::single)
        return;
    for (int i = 0; i < Mpad_; ++i)
    {
        const Mode m = mode(i);
        q_[i] = m.now;
        qPrev_[i] = m.before;
    }
    c1_ = c2_ = 0.0;
    layout_ = Layout::single;
}

void ModalState::beginPairs()
{
    if (layout_ != Layout::single)
        return;
    layout_ = Layout::pairBoundary;  // q = q^n, qPrev = q^{n-1}: the boundary form with c = 0
    c1_ = c2_ = 0.0;
}

void ModalState::setPairMiddle(double c1)
{
    c1_ = c1;
    c2_ = 0.0;
    layout_ = Layout::pairMiddle;
}

void ModalState::setPairBoundary(double c2)
{
    c2_ = c2;
    layout_ = Layout::pairBoundary;
}

void ModalState::useReleased(bool released)
{
    if (released == released_)
        return;
    toSingle();  // the paired layout's corrections use the coefficients of its pass
    released_ = released;
    a_ = released ? aReleased_ : aNormal_;
    e_ = released ? eReleased_ : eNormal_;
}

void ModalState::swapSingle()
{
    std::swap(q_, qPrev_);
}

void ModalState::clear()
{
    std::fill(q_, q_ + Mpad_, 0.0);
    std::fill(qPrev_, qPrev_ + Mpad_, 0.0);
    std::fill(settled_, settled_ + Mpad_, 0.0);
    restartSingle();
}

void ModalState::restartSingle()
{
    layout_ = Layout::single;
    c1_ = c2_ = 0.0;
}

void ModalState::prefetchPass() const
{
    for (int i = 0; i < Mpad_; i += 8)  // a cache line of doubles at a time
    {
        __builtin_prefetch(a_ + i, 0, 3);
        __builtin_prefetch(e_ + i, 0, 3);
        __builtin_prefetch(h_ + i, 0, 3);
        if (hasSecondPickup_)
            __builtin_prefetch(h2_ + i, 0, 3);
        if (phi_ != nullptr)
            __builtin_prefetch(phi_ + i, 0, 3);
        __builtin_prefetch(q_ + i, 1, 3);
        __builtin_prefetch(qPrev_ + i, 1, 3);
        __builtin_prefetch(settled_ + i, 1, 3);
    }
}

}  // namespace jawari
