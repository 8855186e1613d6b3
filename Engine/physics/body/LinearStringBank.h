#pragma once
// Strings held by one spring each and nothing else (the sitar's sympathetic strings on their
// bridge), stepped together on a moving bridge: their modes side by side, one string a lane
// (docs/design.md, "Sympathetic strings"). Each is linear, so its force on the bridge is affine in
// the bridge's displacement, and the bank gives it in closed form: the secant on the bridge
// (SharedBody) needs no solve of theirs per evaluation. Each string's step is the one its own solver
// takes (ModalSolver::LoneSpring), in the single form (a string alone pairs its steps: the same
// motion to rounding), so the energy balance is the solver's.
//
// The strings are taken from their solvers (take) and given back (giveBack) around a run of steps;
// in between their solvers are not to be read. RT: no allocation.

#include "physics/modes/ModalSolver.h"

#include <array>
#include <utility>

namespace jawari
{

class LinearStringBank
{
public:
    static constexpr int kLanes = 16;  // strings
    // Active modes per string: the instrument's sympathetic strings have 16, a scene's as many as its
    // automatic quality gives them.
    static constexpr int kModes = 256;

    static bool fits(const ModalSolver& string) { return string.isLoneSpring(kModes); }

    // RT: the `count` strings' tables and state; false (nothing taken) if there are more than kLanes
    // or one does not fit.
    bool take(ModalSolver* const* strings, int count);
    // RT: their state back into their solvers; the bank is empty after.
    void giveBack(ModalSolver* const* strings);
    int count() const { return count_; }

    // RT: the step's prediction q~ = a q^n - e q^{n-1} and each string's u~ at its spring.
    void predict();
    // RT: sum_i w_i G_i with the bridge at `before` (n-1) and `before + move` (n+1), and (optional)
    // its derivative in `move`.
    double force(double before, double move, double* slope = nullptr) const;
    // RT: the same, kept as the step's solve.
    double solve(double before, double move);
    // RT: the step completed with the last solve.
    void finish();
    // RT: every string at rest (the body silenced).
    void silence();

private:
    using Lanes = std::array<double, kLanes>;
    // Each string's slope G with the bridge at (before, move), into G's first count() lanes.
    void springSlopes(double before, double move, Lanes& G) const;

    int count_ = 0;
    int modes_ = 0;  // the most active modes of any string: the rows stepped (a shorter string's are zero)
    // [mode][string]
    using Table = std::array<Lanes, kModes>;
    alignas(64) Table a_{}, e_{}, phi_{};
    alignas(64) Table q_{};      // q^n
    alignas(64) Table qPrev_{};  // q^{n-1}, then q~ after predict()
    // Per string (the constants of ModalSolver::LoneSpring, and its state).
    alignas(64) Lanes height_{}, stiffness_{}, chordSlope_{}, weight_{}, coupling_{}, stringCoupling_{},
        forceScale_{}, kappa_{}, pushPerSlope_{}, forcePerSlope_{};
    alignas(64) Lanes uTilde_{}, uC_{}, uCPrev_{}, slope_{};
    alignas(64) Lanes delta_{}, deltaPrev_{}, spring_{}, springPrev_{};  // the residual compliance
    std::array<int, kLanes> modesOf_{};
    // Each per-string value and the LoneSpring field it comes from: the constants, taken; the state,
    // taken and given back.
    using Field = std::pair<Lanes LinearStringBank::*, double ModalSolver::LoneSpring::*>;
    static constexpr int kConstants = 10;
    static const std::array<Field, kConstants + 7> kFields;
};

}  // namespace jawari
