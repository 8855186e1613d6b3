#include "realtime/playing/ControlSmoothing.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <iterator>
#include <tuple>

namespace jawari
{

double ControlRule::playable(double target, double value) const
{
    const double finite = std::isfinite(target) ? target : (std::isnan(fallback) ? value : fallback);
    return std::clamp(finite, lowest, highest);
}

bool ControlRule::moves(double value, double target) const
{
    const double goal = playable(target, value);
    if (!glide)
        return goal != value;  // an unplayable target already taken does not move it again
    return geometric ? std::log(goal) != std::log(std::clamp(value, lowest, highest)) : goal != value;
}

double ControlRule::step(double value, double target, double k) const
{
    const double goal = playable(target, value);
    if (!glide)
        return goal;
    auto approach = [&](double now, double to) {
        return std::abs(to - now) <= tolerance || k >= 1.0 ? to : now + k * (to - now);
    };
    return geometric ? std::exp(approach(std::log(std::clamp(value, lowest, highest)), std::log(goal)))
                     : approach(value, goal);
}

namespace
{
using Controls = InstrumentControls;
constexpr InstrumentControls kDefaults{};

// One control of the struct, or every point of one of its arrays, and its rule.
struct Control
{
    double Controls::*value = nullptr;
    ControlRule rule;
};
template <size_t N>
struct ControlArray
{
    std::array<double, N> Controls::*values = nullptr;
    ControlRule rule;
};

// The obstacle: glides; a non-finite target leaves it where it is.
constexpr Control kContactControls[] = {
    {&Controls::obstacleHeight, {.glide = true, .tolerance = 1e-9}},
    {&Controls::stiffness, {.lowest = 1.0, .glide = true, .geometric = true, .tolerance = 1e-6}},
    {&Controls::exponent, {.glide = true, .tolerance = 1e-6}},
};
// The damping law, the decay scale, the reference pitch: jump, then retune.
constexpr Control kDampingControls[] = {
    {&Controls::decayScale, {.fallback = kDefaults.decayScale}},
    {&Controls::airScale, {.fallback = kDefaults.airScale}},
    {&Controls::deltaVe, {.fallback = kDefaults.deltaVe}},
    {&Controls::qTeInv, {.fallback = kDefaults.qTeInv}},
    {&Controls::tuningA4Hz, {.lowest = 200.0, .highest = 1000.0, .fallback = kDefaults.tuningA4Hz}},
};
constexpr ControlArray<kDampingCurvePoints> kDampingCurve{
    &Controls::dampingCurve, {.lowest = kDampingCurveMin, .highest = kDampingCurveMax, .fallback = 1.0}};
// Read where they are used, every chunk. The bend range glides: switched at once it would jump every
// bent string's pitch, and jumps repeated at audio rate pump energy into a string (a retune keeps
// its motion).
constexpr Control kImmediateControls[] = {
    {&Controls::bendRangeSemitones,
     {.lowest = 0.0, .highest = 24.0, .fallback = kDefaults.bendRangeSemitones, .glide = true, .tolerance = 1e-6}},
    {&Controls::gainDb, {.lowest = -120.0, .highest = 24.0, .fallback = kDefaults.gainDb}},
    {&Controls::stereoWidth, {.lowest = 0.0, .highest = 1.0, .fallback = kDefaults.stereoWidth}},
    {&Controls::bodyMix, {.lowest = 0.0, .highest = 1.0, .fallback = kDefaults.bodyMix, .glide = true, .tolerance = 1e-6}},
    {&Controls::droneSaHz, {.lowest = 0.0, .highest = 2000.0, .fallback = 0.0}},
    {&Controls::droneTempo, {.fallback = kDefaults.droneTempo}},
    {&Controls::humanise, {.fallback = 0.0}},
    {&Controls::droneStrength, {.lowest = 0.0, .highest = 1.0, .fallback = kDefaults.droneStrength}},
    {&Controls::sympatheticDamping, {.lowest = 0.1, .highest = 100.0, .fallback = kDefaults.sympatheticDamping}},
    {&Controls::sympatheticLevel,
     {.lowest = 0.0, .highest = 1.0, .fallback = kDefaults.sympatheticLevel, .glide = true, .tolerance = 1e-6}},
};
constexpr size_t kDroneFineTunings = std::tuple_size_v<decltype(kDefaults.droneFineCents)>;
constexpr ControlArray<kDroneFineTunings> kDroneFineCents{&Controls::droneFineCents,
                                                          {.lowest = -100.0, .highest = 100.0, .fallback = 0.0}};
constexpr ControlRule kGain{.glide = true, .tolerance = 1e-6};

template <size_t N>
bool anyMoves(const Control (&group)[N], const Controls& current, const Controls& target)
{
    return std::any_of(std::begin(group), std::end(group),
                       [&](const Control& c) { return c.rule.moves(current.*c.value, target.*c.value); });
}

template <size_t N>
bool anyMoves(const ControlArray<N>& points, const Controls& current, const Controls& target)
{
    for (size_t i = 0; i < N; ++i)
        if (points.rule.moves((current.*points.values)[i], (target.*points.values)[i]))
            return true;
    return false;
}

template <size_t N>
void stepAll(const Control (&group)[N], Controls& current, const Controls& target, double k)
{
    for (const auto& c : group)
        current.*c.value = c.rule.step(current.*c.value, target.*c.value, k);
}

template <size_t N>
void stepAll(const ControlArray<N>& points, Controls& current, const Controls& target, double k)
{
    for (size_t i = 0; i < N; ++i)
        (current.*points.values)[i] = points.rule.step((current.*points.values)[i], (target.*points.values)[i], k);
}
}  // namespace

ControlChanges SmoothedControls::advance(double k)
{
    ControlChanges changes;
    changes.contact = anyMoves(kContactControls, current_, target_);
    if (changes.contact)
        stepAll(kContactControls, current_, target_, k);
    changes.damping = anyMoves(kDampingControls, current_, target_) || anyMoves(kDampingCurve, current_, target_);
    if (changes.damping)
    {
        stepAll(kDampingControls, current_, target_, k);
        stepAll(kDampingCurve, current_, target_, k);
    }
    stepAll(kImmediateControls, current_, target_, k);
    stepAll(kDroneFineCents, current_, target_, k);
    current_.drone = target_.drone;
    current_.droneTonic = target_.droneTonic;
    current_.droneFirst = target_.droneFirst;
    current_.droneTuning = target_.droneTuning;
    current_.sympatheticScale = target_.sympatheticScale;
    current_.sympatheticIntonation = target_.sympatheticIntonation;
    gain_ = kGain.step(gain_, std::pow(10.0, current_.gainDb / 20.0), k);
    return changes;
}

}  // namespace jawari
