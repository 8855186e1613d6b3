// The split step over many modes: of the points within reach, only those the high modes may carry
// to their obstacle are projected in full and solved (EngagedPoints.h; docs/design.md section 2).
#include "physics/modes/ModalSolver.h"

#include "physics/modes/ModalKernels.h"

namespace jawari
{

void ModalSolver::measureTail()
{
    const int low = EngagedPoints::kLowModes;
    if (engaged_.splits(state_.activeCount()))
        reach_.measureTail(state_.activeModes() + low, state_.activeCount() - low, shapes_, mu_);
}

// Before the prediction, with q^n and q^{n-1} in place: every live point that a split step left out
// gets its u^n and u^{n-1}, as a point joining the reach does.
void ModalSolver::engageEveryPoint()
{
    const int* rows = reach_.liveRows();
    for (int k = 0; k < reach_.liveCount(); ++k)
        if (!engaged_.engaged(rows[k]))
            projectPoint(rows[k]);
    engaged_.engageAll();
}

// After q~ was written over q^{n-1}: low_j over the low modes at every live point, the engaged ones
// chosen by the high modes' reach R_j, and their u~ completed over the high modes (the same sums as
// projectRows over all the modes). A point is clear while u > its obstacle's height.
void ModalSolver::predictSplit()
{
    const double* next = state_.qPrev();
    const int low = EngagedPoints::kLowModes;
    const int live = reach_.liveCount();
    const int* rows = reach_.liveRows();
    engaged_.clearLanes(rows, live);
    kernels::projectRowsPart(state_.phi(0), state_.stride(), rows, live, next, 0, low, engaged_.lanes());
    const double radius = reach_.radius();
    for (int k = 0; k < live; ++k)
    {
        const int j = rows[k];
        const double lowSum = kernels::sum8(engaged_.lanes(j));
        engaged_.low(j) = lowSum;
        const double reach = radius * reach_.tail(j);
        const double height = contacts_[size_t(j)].height;
        if (engaged_.engaged(j))
        {
            // Out only when clear by twice the reach (so that it does not come straight back) and off
            // its obstacle at n and n-1, so that its force is zero however this step ends.
            if (lowSum - 2.0 * reach > height && uC_[j] >= height && uCPrev_[j] >= height)
            {
                engaged_.disengage(j);
                slope_[j] = 0.0;
            }
        }
        else if (!(lowSum - reach > height))  // NaN: engaged
            engageMidStep(j);
    }
    engaged_.collect(rows, live);
    completePredictions(engaged_.rows(), engaged_.count());
}

// u~ at these points: their low modes' lanes carried on over the high modes, summed as projectRows sums.
void ModalSolver::completePredictions(const int* rows, int count)
{
    kernels::projectRowsPart(state_.phi(0), state_.stride(), rows, count, state_.qPrev(), EngagedPoints::kLowModes,
                             state_.paddedCount(), engaged_.lanes());
    for (int k = 0; k < count; ++k)
        uTilde_[rows[k]] = kernels::sum8(engaged_.lanes(rows[k]));
}

// Point j engaged after the prediction: u^n and u^{n-1} afresh (projectPointMidStep). Its u~ is
// completed with the other engaged points' (predictSplit) or at once (engageReached).
void ModalSolver::engageMidStep(int j)
{
    projectPointMidStep(j);
    engaged_.engage(j);
    ++engaged_.counters.joins;
}

// After a solve of the engaged points: u^{n+1}_j >= low_j - R_j + (A f)_j at each other live point;
// those that may reach their obstacle are engaged, their u~ completed and their equations posed.
// Whether any was (then the caller solves again).
bool ModalSolver::engageReached()
{
    const double radius = reach_.radius();
    const int live = reach_.liveCount();
    const int* rows = reach_.liveRows();
    const int* engagedRows = engaged_.rows();
    const int engagedCount = engaged_.count();
    bool any = false;
    for (int k = 0; k < live; ++k)
    {
        const int j = rows[k];
        if (engaged_.engaged(j))
            continue;
        double Af = 0.0;
        for (int l = 0; l < engagedCount; ++l)
            if (const int i = engagedRows[l]; slope_[i] != 0.0)
                Af -= stringCoupling_(j, i) * slope_[i];
        if (engaged_.low(j) - radius * reach_.tail(j) + Af > contacts_[size_t(j)].height)
            continue;
        engageMidStep(j);
        completePredictions(&j, 1);
        poseContactEquation(j);
        slope_[j] = 0.0;
        any = true;
    }
    if (any)
        engaged_.collect(rows, live);
    return any;
}

}  // namespace jawari
