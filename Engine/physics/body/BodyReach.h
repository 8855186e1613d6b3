#pragma once
// Which contact points each string on a shared body takes (SharedBody): the points out of reach
// are left out of its solve as a lone string leaves them (ContactReach, docs/design.md section 2),
// from budgets that each step's own energy balance keeps.
//
// A string alone never gains energy, so its energy H at a check bounds its motion until the next.
// On a body it gains what the bridge's motion does on it: by the discrete energy balance, string
// i's energy (its modes, its obstacles' potential, its residual compliance) changes in a step by
//   -F_i (W - w^{n-1}) / 2  minus its losses,
// with F_i = sum_j w_j G_j its points' force on the bridge (< 0 while it presses the bridge down)
// and W, w^{n-1} the bridge's displacement at n+1 and n-1: a bridge that rises under a string
// pressing on it gives it energy. So at each check every string gets a budget, its energy then and
// a margin for what the bridge may give it (from what it gave over the last interval of the same
// strings; twice the energy at the first check), and the bridge a rise, twice the highest it rose
// since the last check (only a rise brings an obstacle nearer); each string's points are chosen for
// them (ContactReach::refresh). After each step's solve, the work is added to what each string has
// spent: a string still within its budget with the bridge within its rise cannot have
// reached a point left out (its displacement there is bounded by its energy, which is at most the
// budget; the obstacle by the rise), so the step, solved without them, is the step with them. A
// step beyond either is solved again with every point live (SharedBody), and the next step checks
// afresh. A check is also due every ContactReach::kCheckSteps steps (the budgets follow the decay),
// when a string's energy may have risen otherwise (ModalSolver::reachStale) or the strings change;
// while a force pushes any string, every point of every string is live. One way, the bridge stands
// still and a string's energy never rises: each takes its own, as alone.

#include "physics/modes/ModalSolver.h"

#include <array>

namespace jawari
{

class BodyReach
{
public:
    static constexpr int kMostStrings = 64;  // more on one body: every point of every string live

    // RT, before the strings predict: their live points, chosen afresh when due, for the bridge at
    // `bridge` now and `before` a step earlier.
    void choose(ModalSolver* const* strings, int count, bool oneWay, double bridge, double before);
    // RT, after the step's solve: whether the first `count` strings, with forces[i] on the bridge as
    // it moved from `before` to `bridge`, stayed within their budgets and the bridge within its
    // rise. If they did, the step's work is counted; if not, the caller solves the step again with
    // every point live.
    bool withinBudgets(const double* forces, int count, double before, double bridge);
    // RT: the live points chosen afresh at the next step.
    void chooseAgain() { chosenCount_ = -1; }

private:
    bool sameStrings(ModalSolver* const* strings, int count);
    void wakeAll(ModalSolver* const* strings, int count);

    std::array<const ModalSolver*, kMostStrings> chosenFor_{};
    std::array<double, kMostStrings> spent_{}, budget_{};  // J: each string's energy bound, and its budget
    std::array<double, kMostStrings> start_{}, gained_{};  // J: its energy at the check, the most it gained since
    bool gainsKnown_ = false;                              // gained_ covers an interval of the strings chosen for
    double rise_ = 0.0;        // m: how high the bridge may rise for the points chosen
    double largestBridge_ = 0.0;  // m: the highest w since the last check (0 if it only sank)
    int chosenCount_ = -1, stepsToCheck_ = 0;
    bool budgeted_ = false;  // the points were chosen for budgets that the steps must keep
};

}  // namespace jawari
