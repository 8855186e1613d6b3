#pragma once
// Of the points within reach (ContactReach), those that a step over many modes projects in full and
// solves (docs/design.md section 2, "Engaged points").
//
// A string of thousands of modes over a bridge of hundreds of points (the reference at its finest)
// spends its step reading Phi, P x M doubles that no cache holds. Most of those points are far from
// their obstacle by more than the string's high modes can carry them. So the active modes are split
// at kLowModes: every live point's prediction is summed over the low modes (low_j), and the high
// modes' share is at most R_j = sqrt(H) tail_j (ContactReach::measureTail). A point is engaged, its
// sum completed over the high modes and its equation solved, when low_j - R_j may reach its
// obstacle; an engaged point stays engaged until low_j - 2 R_j clears it and it is off its obstacle
// at n and n-1. After the solve, each other live point j is checked with the forces' response:
// u_j^{n+1} >= low_j - R_j + (A f)_j; one that may reach its obstacle is engaged and the step solved
// again. A point left out is off its obstacle at n-1 and n+1, so its force is zero and leaving it
// out changes nothing: the step is the one over every live point, to rounding.
//
// An engaged point's u^n and u^{n-1} are kept exact as the step goes; a point that was out is given
// them afresh when it is engaged. Unilateral points, energy-conserving method, no residual
// compliance and no explicit force: otherwise every live point is engaged.

#include <cstddef>
#include <vector>

namespace jawari
{

class EngagedPoints
{
public:
    static constexpr int kLowModes = 256;  // a multiple of 8: the kernels' lanes

    // OFF: `points` contact points; not `enabled`: never splits (every live point engaged).
    void prepare(int points, bool enabled);
    // Whether a step over `activeModes` active modes splits them (at least four times the low modes).
    bool splits(int activeModes) const { return enabled_ && activeModes >= 4 * kLowModes; }

    bool engaged(int j) const { return engaged_[std::size_t(j)] != 0; }
    void engage(int j) { engaged_[std::size_t(j)] = 1; }
    void disengage(int j)
    {
        engaged_[std::size_t(j)] = 0;
        anyOut_ = true;
    }
    // RT: whether a point may be out (its u^n and u^{n-1} not kept) since engageAll().
    bool anyOut() const { return anyOut_; }
    void engageAll();

    // RT: the engaged ones among `live` rows, ascending, as rows().
    void collect(const int* live, int count);
    const int* rows() const { return rows_.data(); }
    int count() const { return count_; }

    // Point j's eight partial sums of its projection (kernels::projectRowsPart), and its low modes' sum.
    double* lanes() { return lanes_.data(); }
    const double* lanes(int j) const { return lanes_.data() + 8 * std::size_t(j); }
    void clearLanes(const int* rows, int count);
    double& low(int j) { return low_[std::size_t(j)]; }

    // Over the run, for the caller's report (RenderStats): split steps, the points they solved (summed),
    // points engaged afresh, and steps solved again.
    struct Counters
    {
        long long steps = 0, engaged = 0, joins = 0, resolves = 0;
    };
    Counters counters;

private:
    bool enabled_ = false;
    bool anyOut_ = false;
    std::vector<char> engaged_;
    std::vector<int> rows_;
    int count_ = 0;
    std::vector<double> lanes_;  // P x 8
    std::vector<double> low_;    // P
};

}  // namespace jawari
