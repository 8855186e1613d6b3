#pragma once
// The per-mode damping curve: kDampingCurvePoints multipliers of each mode's damping, at
// frequencies log-spaced from 20 Hz to 20 kHz, log-log interpolated between them.

#include <array>

namespace jawari
{

inline constexpr int kDampingCurvePoints = 12;
inline constexpr double kDampingCurveMin = 0.125;  // the multipliers' range
inline constexpr double kDampingCurveMax = 8.0;

// The frequency of the curve's point i (Hz): 20 * 1000^(i / (points - 1)). RT.
double dampingCurveFrequency(int i);
// The curve's multiplier at f: exp of the linear interpolation of the logarithms at the fractional
// point log(f / 20) / log(1000) * (points - 1), flat beyond the ends. RT.
double dampingCurveAt(const std::array<double, kDampingCurvePoints>& curve, double frequencyHz);

}  // namespace jawari
