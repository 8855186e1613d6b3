#include "physics/body/BodyReach.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace jawari
{

namespace
{
constexpr double kHeadroom = 2.0;  // a first budget is this many times the energy at the check; the rise, the highest w
// Once the same strings have run an interval, a budget is the energy at the check with a margin of
// kGainHeadroom times the most the bridge gave the string over the interval before, and at least
// kLeastMargin of that energy.
constexpr double kGainHeadroom = 4.0;
constexpr double kLeastMargin = 0.05;
// A string at rest still gets this share of the largest string's energy as its budget: the body
// wakes it slowly.
constexpr double kLeastShare = 1e-6;
}  // namespace

// Whether the strings are those the live points were last chosen for (and they are now).
bool BodyReach::sameStrings(ModalSolver* const* strings, int count)
{
    bool same = count == chosenCount_;
    for (int i = 0; i < count && same; ++i)
        same = chosenFor_[size_t(i)] == strings[i];
    if (!same)
    {
        std::copy(strings, strings + count, chosenFor_.begin());
        chosenCount_ = count;
    }
    return same;
}

void BodyReach::wakeAll(ModalSolver* const* strings, int count)
{
    for (int i = 0; i < count; ++i)
        strings[i]->wakeAllPoints();
    budgeted_ = false;
    chosenCount_ = -1;  // chosen again once nothing pushes
}

void BodyReach::choose(ModalSolver* const* strings, int count, bool oneWay, double bridge, double before)
{
    largestBridge_ = std::max({largestBridge_, bridge, before});  // the highest: only a rise brings an obstacle nearer
    bool pushed = count > kMostStrings;
    for (int i = 0; i < count && !pushed; ++i)
        pushed = strings[i]->pushed();
    if (pushed)
        return wakeAll(strings, count);
    const bool same = sameStrings(strings, count);
    bool due = !same || --stepsToCheck_ <= 0;
    for (int i = 0; i < count && !due; ++i)
        due = strings[i]->reachStale();
    if (!due)
        return;
    stepsToCheck_ = ContactReach::kCheckSteps;
    budgeted_ = false;
    if (oneWay)
    {
        gainsKnown_ = false;  // the bridge gives nothing one way: two way starts again from twice the energy
        for (int i = 0; i < count; ++i)
            strings[i]->refreshReachOnBridge(strings[i]->energyOnBridge(0.0, 0.0), 0.0);
        return;
    }
    double largest = 0.0;
    for (int i = 0; i < count; ++i)
    {
        spent_[size_t(i)] = strings[i]->energyOnBridge(bridge, before);
        largest = std::max(largest, spent_[size_t(i)]);
    }
    rise_ = kHeadroom * largestBridge_;
    largestBridge_ = 0.0;
    const bool gainsKnown = same && gainsKnown_;
    for (int i = 0; i < count; ++i)
    {
        const double H = spent_[size_t(i)];
        const double margin =
            gainsKnown ? std::max(kGainHeadroom * gained_[size_t(i)], kLeastMargin * H) : (kHeadroom - 1.0) * H;
        budget_[size_t(i)] = H + margin + kLeastShare * largest;
        start_[size_t(i)] = H;
        gained_[size_t(i)] = 0.0;
        strings[i]->refreshReachOnBridge(budget_[size_t(i)], rise_);
        if (strings[i]->livePointCount() == strings[i]->contactCount())
            budget_[size_t(i)] = std::numeric_limits<double>::infinity();  // every point live: nothing to keep
        else
            budgeted_ = true;
    }
    gainsKnown_ = budgeted_;  // the steps count the gifts only while some string is budgeted
}

// With every point of every string live, nothing can be out of reach.
bool BodyReach::withinBudgets(const double* forces, int count, double before, double bridge)
{
    if (!budgeted_)
        return true;
    if (bridge > rise_)
        return false;
    const double halfMove = 0.5 * (bridge - before);
    for (int i = 0; i < count; ++i)
        if (spent_[size_t(i)] - forces[i] * halfMove > budget_[size_t(i)])
            return false;
    for (int i = 0; i < count; ++i)
    {
        spent_[size_t(i)] -= forces[i] * halfMove;
        gained_[size_t(i)] = std::max(gained_[size_t(i)], spent_[size_t(i)] - start_[size_t(i)]);
    }
    return true;
}

}  // namespace jawari
