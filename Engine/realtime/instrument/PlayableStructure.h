#pragma once
// The plugin's structure as the physics accepts it. Whatever a host, a saved state or a preset
// sets (NaN, infinities, values past any range, an enum out of its list), the pack is built from
// a structure with every field finite and inside what the solver, the obstacles and the decimator
// take: a bad value never reaches a constructor that would refuse it.

#include "realtime/instrument/InstrumentSettings.h"

namespace jawari
{

// Every field of s made playable: a value that is not a number takes the default
// (InstrumentStructure{}), and a finite one is clamped to its range. A parabolic bridge wider than
// its distance from an end is moved along the string (its width kept) until it lies on it; a
// thread stays on its bridge. The host rate is passed through (the caller checks it). OFF.
InstrumentStructure playableStructure(const InstrumentStructure& s);

// The widest obstacle the instrument plays (m): the plugin's range.
inline constexpr double kWidestObstacleMetres = 0.05;

// Whether a host rate can be played (8 kHz to 384 kHz, the decimator's and the scenes' range).
bool playableHostRate(double hostRateHz);

}  // namespace jawari
