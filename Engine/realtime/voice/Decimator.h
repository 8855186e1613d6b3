#pragma once
// Integer-factor decimation from the voice's internal rate R = factor x host rate to the host rate.
// A linear-phase low-pass FIR designed by liquid-dsp's Kaiser-window routine (liquid_firdes_kaiser,
// length from estimate_req_filter_len): passband to min(20 kHz, 0.45 host rate), stopband from the
// host Nyquist frequency, 100 dB design attenuation, so nothing aliases back at all.
// Timing: host output m stands for the internal sample m F (F the factor) delayed by a whole number
// of host samples, the latency L: output m is the string at t = (m - L)/host rate, as the
// reference's sample m - L is. The filter is centred on the first internal sample of each block of
// F, so (length - 1)/2 = L F + F - 1. The taps are made exactly symmetric, and the output costs one
// multiply per pair of taps.

#include <vector>

namespace jawari
{

class Decimator
{
public:
    // OFF: designs the filter and sizes the history. factor 1 is a pass-through (latency 0).
    Decimator(int factor, double hostRateHz);

    int factor() const { return factor_; }
    int length() const { return static_cast<int>(taps_.size()); }
    int latencyHostSamples() const { return latency_; }
    double passbandHz() const { return passbandHz_; }
    const std::vector<double>& taps() const { return taps_; }

    // RT: takes `factor` internal samples, returns one host sample.
    double process(const double* internal);
    void reset();  // RT: clears the history
    // RT: the history as if the input had held `value` for ever: a signal that starts at t = 0 from
    // a held state (a string released from rest in a shape) starts without a step.
    void prime(double value);

private:
    int factor_ = 1;
    int latency_ = 0;
    double passbandHz_ = 0.0;
    std::vector<double> taps_;  // time-reversed, so the output is a plain dot product
    // The last `length` samples twice over (each sample written twice, so a window is contiguous):
    // oldest first in history_, newest first in reversed_. The filter is linear-phase (symmetric
    // taps), so the output pairs sample i with sample length-1-i: one multiply per pair.
    std::vector<double> history_, reversed_;
    int position_ = 0, reversedPosition_ = 0;
};

}  // namespace jawari
