#include "realtime/voice/DampingCurve.h"

#include <algorithm>
#include <cmath>

namespace jawari
{

double dampingCurveFrequency(int i)
{
    return 20.0 * std::pow(1000.0, double(i) / double(kDampingCurvePoints - 1));
}

double dampingCurveAt(const std::array<double, kDampingCurvePoints>& curve, double frequencyHz)
{
    const double position = std::log(std::max(frequencyHz, 1e-3) / 20.0) / std::log(1000.0) * (kDampingCurvePoints - 1);
    if (!(position > 0.0))
        return curve.front();
    if (position >= kDampingCurvePoints - 1)
        return curve.back();
    const int i = static_cast<int>(position);
    const double t = position - i;
    return std::exp((1.0 - t) * std::log(curve[size_t(i)]) + t * std::log(curve[size_t(i) + 1]));
}

}  // namespace jawari
