#pragma once
// Band-limits and resamples the internal-rate pickup signal to the output rate, at any ratio
// (the reference runs at 2 MHz and writes 48 kHz: a ratio of 125/3). libsoxr's very-high-quality
// linear-phase filter (28-bit precision, double-precision arithmetic, flat to 0.913 of the output
// Nyquist, no aliasing above it), delay-compensated: output sample m is the signal at t = m/rate.
// OFF (soxr allocates as it streams).

#include <cstddef>
#include <vector>

struct soxr;

namespace jawari
{

class Resampler
{
public:
    Resampler(double inputRateHz, double outputRateHz);
    ~Resampler();
    Resampler(const Resampler&) = delete;
    Resampler& operator=(const Resampler&) = delete;

    // Appends what is ready to `out`.
    void push(const double* input, size_t count, std::vector<double>& out);
    // Drains the filter (end of input).
    void finish(std::vector<double>& out);

private:
    soxr* soxr_ = nullptr;
    std::vector<double> buffer_;
};

}  // namespace jawari
