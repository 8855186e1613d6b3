#include "realtime/voice/Decimator.h"

#include "physics/modes/ModalKernels.h"

#include <liquid/liquid.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace jawari
{

Decimator::Decimator(int factor, double hostRateHz)
    : factor_(factor)
{
    if (factor < 1 || factor > 256)
        throw std::invalid_argument("decimation factor must be 1 to 256, got " + std::to_string(factor));
    passbandHz_ = std::min(20000.0, 0.45 * hostRateHz);
    if (factor == 1)
    {
        taps_ = {1.0};
        history_.assign(2, 0.0);
        reversed_.assign(2, 0.0);
        return;
    }
    const double internalRate = factor * hostRateHz;
    const double stopbandHz = 0.5 * hostRateHz;
    const double attenuationDb = 100.0;
    const float transition = static_cast<float>((stopbandHz - passbandHz_) / internalRate);
    const unsigned int estimate = estimate_req_filter_len(transition, static_cast<float>(attenuationDb));
    // Output m is computed once internal sample mF + F - 1 has arrived, and the filter's centre
    // lies (n - 1)/2 samples before it. With (n - 1)/2 = qF + F - 1 the centre is internal sample
    // (m - q)F, the string at exactly t = (m - q)/host rate: a delay of q whole host samples.
    const unsigned int F = static_cast<unsigned int>(factor);
    // The smallest q with qF + F - 1 >= (estimate - 1)/2.
    const unsigned int q = (estimate - 1) / 2 / F;
    const unsigned int n = 2u * (q * F + F - 1) + 1;
    std::vector<float> h(n);
    const float cutoff = static_cast<float>(0.5 * (passbandHz_ + stopbandHz) / internalRate);
    if (liquid_firdes_kaiser(n, cutoff, static_cast<float>(attenuationDb), 0.0f, h.data()) != 0)
        throw std::runtime_error("liquid_firdes_kaiser failed for a decimator of length " + std::to_string(n));
    double sum = 0.0;
    for (float v : h)
        sum += v;
    taps_.resize(n);
    for (unsigned int i = 0; i < n; ++i)
        // Unit gain at DC; time-reversed, which for these symmetric taps is the same order. Pairs are
        // averaged so the symmetry holds exactly (the design is symmetric to float rounding).
        taps_[i] = 0.5 * (static_cast<double>(h[n - 1 - i]) + static_cast<double>(h[i])) / sum;
    latency_ = static_cast<int>(q);
    history_.assign(2 * n, 0.0);
    reversed_.assign(2 * n, 0.0);
}

void Decimator::reset()
{
    std::fill(history_.begin(), history_.end(), 0.0);
    std::fill(reversed_.begin(), reversed_.end(), 0.0);
    position_ = reversedPosition_ = 0;
}

void Decimator::prime(double value)
{
    std::fill(history_.begin(), history_.end(), value);
    std::fill(reversed_.begin(), reversed_.end(), value);
}

double Decimator::process(const double* internal)
{
    const int n = length();
    if (n == 1)
        return internal[factor_ - 1];
    for (int i = 0; i < factor_; ++i)
    {
        history_[position_] = internal[i];
        history_[position_ + n] = internal[i];
        if (++position_ == n)
            position_ = 0;
        reversedPosition_ = (reversedPosition_ == 0 ? n : reversedPosition_) - 1;
        reversed_[reversedPosition_] = internal[i];
        reversed_[reversedPosition_ + n] = internal[i];
    }
    // history_[position_ .. position_ + n) holds the last n samples oldest first, reversed_ from
    // reversedPosition_ newest first; n is odd, and the middle tap pairs with nothing.
    const int half = n / 2;
    const double* oldest = history_.data() + position_;
    return kernels::pairedDot(taps_.data(), oldest, reversed_.data() + reversedPosition_, half)
           + taps_[size_t(half)] * oldest[half];
}

}  // namespace jawari
