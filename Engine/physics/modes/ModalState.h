#pragma once
// The modes a solver steps, and the arrays it steps them in (docs/design.md section 2).
//
// Active modes: a mode that no contact point (nor the excitation) couples to, and that starts at
// zero, stays at zero; it is left out of the pass. The arrays (coefficients of both damping sets,
// pickup weights, excitation and contact shapes, the state) are padded to whole kernel blocks
// (padding modes are zero and stay zero) and live in one 64-byte-aligned block, `stride` doubles
// apart, the stride staggered modulo 4 KiB: arrays exactly 4 KiB apart make every load alias the
// stores of the pass (measured: 501 modes padded to 512 ran 1.7x slower).
//
// Layouts. With at most one contact point the solver advances two steps per pass
// (kernels::pairStep), and between passes the arrays hold the state in a paired form with the
// scalar corrections c1, c2 of the contact forces:
//   single:        q^n = q,                        q^{n-1} = qPrev;
//   pairBoundary:  q^n = q + (c1 a + c2) phi,      q^{n-1} = qPrev + c1 phi;
//   pairMiddle:    q^n = qPrev + c1 phi,           q^{n-1} = settled  (q holds the pair's raw second step).
// mode(i) decodes any layout; toSingle() rewrites the arrays in the single layout.

#include "physics/modes/ExactOscillator.h"
#include "physics/modes/ModalKernels.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace jawari
{

enum class ModalLayout
{
    single,
    pairBoundary,
    pairMiddle
};

// ModalState's members in three groups, each copied as a whole by ModalState::operator= (so a member
// added to a group cannot be left out of the copy): the scalars, always; the tables over the active
// modes, unless the copy has them already; the pointers into the arrays, rebased.
struct ModalStateScalars
{
    int M_ = 0;     // modes of the model
    int Ma_ = 0;    // modes stepped (active)
    int Mpad_ = 0;  // Ma_ rounded up to the kernels' block
    int stride_ = 0;
    int pickupCount_ = 0;
    int contactCount_ = 0;
    bool pairable_ = false;
    bool hasSecondPickup_ = false;
    ModalLayout layout_ = ModalLayout::single;
    double c1_ = 0.0, c2_ = 0.0;
    double sumAPhiSquared_[2] = {0.0, 0.0}, sumAPhiH_[2] = {0.0, 0.0}, sumAPhiH2_[2] = {0.0, 0.0};  // per damping set
    int steepFrom_[2] = {0, 0};  // per damping set: steepFrom()
    uint64_t tablesStamp_ = 0;  // new at each compact() and fillTables() (StampedVector.h)
    bool released_ = false;
};

struct ModalStateTables
{
    std::vector<int> active_;
    std::vector<int> indexOfMode_;  // active index of mode p, or -1
    std::vector<ExactModeCoefficients> activeNormal_, activeReleased_;
};

struct ModalStateArrays  // into ModalState's storage, 64-byte aligned, stride_ apart
{
    double* a_ = nullptr;  // the coefficient set in use (normal or released)
    double* e_ = nullptr;
    double* aNormal_ = nullptr;
    double* eNormal_ = nullptr;
    double* aReleased_ = nullptr;
    double* eReleased_ = nullptr;
    double* h_ = nullptr;
    double* h2_ = nullptr;
    double* phiE_ = nullptr;  // excitation shape over the active modes
    double* phi_ = nullptr;   // contact rows, stride_ apart (none on the DST path)
    double* q_ = nullptr;
    double* qPrev_ = nullptr;
    double* settled_ = nullptr;
};

class ModalState : private ModalStateScalars, private ModalStateTables, private ModalStateArrays
{
public:
    ModalState() = default;
    ModalState(const ModalState&) = delete;
    // RT: the other's exact copy in arrays of its own (the pointers rebased into them). Into a state
    // of the same modes and contact rows, nothing is allocated. When this already holds the other's
    // tables (the same tables stamp: copied from it, or from a common copy, with no compact() or
    // fillTables() since), only the state arrays and the scalars are copied.
    ModalState& operator=(const ModalState& other);

    using Layout = ModalLayout;
    struct Mode
    {
        double now = 0.0;     // q^n
        double before = 0.0;  // q^{n-1}
    };

    // OFF: the active modes of a model of current.size() modes (coupled ones, and those not zero
    // in the state to 1e-13 of its largest value), their state, excitation shape and the rows of
    // `contactShapes` (contactCount x M, phi_p(x_j)); `exactSize`: no padding (the DST path works
    // on exactly M values). `pairable`: one or no contact point, so the solver may pair steps.
    void compact(const std::vector<char>& coupled, const std::vector<double>& current,
                 const std::vector<double>& previous, const std::vector<double>& excitationShape,
                 const std::vector<double>& contactShapes, int contactCount, bool exactSize, bool pairable);
    // RT: the active modes' coefficients of both damping sets and pickup weights (and a second
    // pickup's, when not empty), from tables over every mode, and the pairing sums.
    void fillTables(const std::vector<ExactModeCoefficients>& normal,
                    const std::vector<ExactModeCoefficients>& released, const std::vector<double>& pickupWeights,
                    const std::vector<double>& secondPickupWeights);

    int modeCount() const { return M_; }
    int activeCount() const { return Ma_; }
    int paddedCount() const { return Mpad_; }
    // Whether the modes are padded to whole kernel blocks with zeros (not the DST path's exact size).
    bool padded() const { return Mpad_ % kernels::kBlock == 0; }
    // Padded: the active modes rounded up to a vector of 8, at most paddedCount(), the modes a pass
    // must cover (the padding beyond is zero and stays so; kernels::pairStep's part blocks).
    int steppedCount() const { return padded() ? std::min(Mpad_, (Ma_ + 7) / 8 * 8) : Mpad_; }
    int stride() const { return stride_; }
    // The leading active modes the pickups read: up to the last with a nonzero weight (the modes
    // above the pickup band have none: ModalSolverConfig::pickupBandHz), rounded up to a kernel
    // block, at most paddedCount(). The kernels read no pickup weight beyond it.
    int pickupCount() const { return pickupCount_; }
    int activeMode(int i) const { return active_[size_t(i)]; }
    const int* activeModes() const { return active_.data(); }  // activeMode(i) for i < activeCount()
    int indexOfMode(int p) const { return p < M_ ? indexOfMode_[size_t(p)] : -1; }  // -1: not active
    bool pairable() const { return pairable_; }

    // RT: (q^n, q^{n-1}) of active mode i, whatever the layout.
    Mode mode(int i) const;
    Layout layout() const { return layout_; }
    // RT: rewrites a paired layout as the single one.
    void toSingle();
    // RT, single layout: each active mode's state divided by ratio[p] and its contact and excitation
    // shapes multiplied by it (p = q / sqrt(gamma) after the static-exact forcing's gains change).
    void rescaleModes(const double* ratio);
    // RT: the single layout read as the boundary of a pair (c1 = c2 = 0).
    void beginPairs();
    // RT: after kernels::pairStep; c1 the first step's correction.
    void setPairMiddle(double c1);
    // RT: after the second step of a pair; c2 its correction.
    void setPairBoundary(double c2);
    double c1() const { return c1_; }
    double c2() const { return c2_; }

    // RT: the damping set in use: the string's own, or with the release damping added.
    void useReleased(bool released);
    bool released() const { return released_; }
    const ExactModeCoefficients& coefficients(int i) const
    {
        return released_ ? activeReleased_[size_t(i)] : activeNormal_[size_t(i)];
    }
    // sum_i a_i phi_i^2 and sum_i a_i phi_i h_i over the active modes, for the set in use.
    double sumAPhiSquared() const { return sumAPhiSquared_[released_ ? 1 : 0]; }
    double sumAPhiH() const { return sumAPhiH_[released_ ? 1 : 0]; }
    double sumAPhiH2() const { return sumAPhiH2_[released_ ? 1 : 0]; }  // the second pickup's

    // The stepping arrays (paddedCount() values each).
    const double* a() const { return a_; }
    const double* e() const { return e_; }
    // The first active mode (of the coefficient set in use) with e < 1e-2, or activeCount(): from
    // there on q^{n-1} = (a q^n - q~) / e could multiply q~'s rounding by more than 100, so whoever
    // needs q^{n-1} after q~ was written over it keeps those modes' own (ModalSolver).
    int steepFrom() const { return steepFrom_[released_ ? 1 : 0]; }
    const double* h() const { return h_; }
    const double* h2() const { return hasSecondPickup_ ? h2_ : nullptr; }  // the second pickup's weights, or null
    const double* phiE() const { return phiE_; }
    const double* phi(int j) const { return phi_ + size_t(j) * stride_; }            // contact row j
    const double* singlePhi() const { return contactCount_ == 1 ? phi_ : nullptr; }  // the one contact row
    double* q() { return q_; }
    double* qPrev() { return qPrev_; }
    double* settled() { return settled_; }
    const double* q() const { return q_; }
    const double* qPrev() const { return qPrev_; }
    // RT: after a single step written over qPrev: q^{n+1} becomes q.
    void swapSingle();
    // RT: asks the cache for the arrays the next pass over the modes reads and writes (the string
    // bank steps many strings in turn, whose arrays do not all fit in the first-level cache).
    void prefetchPass() const;
    // RT: the state at rest (zero), single layout.
    void clear();
    // RT: single layout from an explicit active-mode state.
    void set(int i, double now, double before)
    {
        q_[i] = now;
        qPrev_[i] = before;
    }
    void restartSingle();  // RT: the single layout, corrections cleared (the caller writes q, qPrev)

private:
    double* alignedBase();  // storage_'s first 64-byte-aligned double: where the arrays start
    // The arrays' values (with stateOnly, q, qPrev and settled only), every pointer rebased.
    void copyArraysFrom(const ModalState& other, bool stateOnly);

    std::vector<double> storage_;  // the arrays (ModalStateArrays point into it)
};

}  // namespace jawari
