#pragma once
// The instrument's controls as played. Every control follows its target (what the host last set)
// by one ControlRule; the instrument steps them all once a chunk. RT throughout: no allocation.

#include "realtime/instrument/InstrumentSettings.h"

#include <limits>

namespace jawari
{

// How one control follows its target. The target is first made playable: a value that is not a
// number becomes `fallback` (or, with a NaN fallback, leaves the control where it is), then it is
// clamped to [lowest, highest]. A jump takes it at once. A glide moves the value by the chunk's
// one-pole step k, v + k (target - v), landing on the target when k reaches 1 or once within
// `tolerance` of it; a geometric glide does so in log(v) (the value clamped to the range first).
struct ControlRule
{
    static constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
    static constexpr double kInfinity = std::numeric_limits<double>::infinity();
    double lowest = -kInfinity, highest = kInfinity;
    double fallback = kNone;
    bool glide = false;
    bool geometric = false;
    double tolerance = 0.0;

    double playable(double target, double value) const;  // the target made playable
    // Whether the value is to move: it is not at its playable target (for a geometric glide, in
    // log(v)).
    bool moves(double value, double target) const;
    double step(double value, double target, double k) const;  // the value one chunk on
};

// Which effects of the controls a chunk's step changed: the obstacle's (re-apply the contact law)
// or the damping and tuning (retune every sounding string).
struct ControlChanges
{
    bool contact = false;
    bool damping = false;
};

// The controls' targets and their values as played. The obstacle's height, stiffness
// (geometrically) and exponent, the bend range, the body's mix and the output gain glide through a 20 ms one-pole; every other
// control jumps (the damping and tuning then retune the strings). The controls of one effect move
// together: when any of them moves, all of them take their step.
class SmoothedControls
{
public:
    void setTarget(const InstrumentControls& controls) { target_ = controls; }  // RT
    const InstrumentControls& target() const { return target_; }
    const InstrumentControls& current() const { return current_; }  // every value playable
    double gain() const { return gain_; }                           // linear, smoothed

    // One chunk with the 20 ms one-pole's step k over it (1: every control lands). RT.
    ControlChanges advance(double k);

private:
    InstrumentControls target_, current_;
    double gain_ = 1.0;
};

}  // namespace jawari
