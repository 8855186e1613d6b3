#pragma once
// Signal measures for accuracy (docs/design.md section 4) and for the physics tests. OFF.

#include <cstddef>
#include <vector>

namespace jawari
{

// Ideal low-pass by FFT: every bin above cutoffHz set to zero.
std::vector<double> lowpass(const std::vector<double>& signal, double rateHz, double cutoffHz);

// ||y - ref|| / ||ref|| over the first `count` samples.
double relativeL2(const std::vector<double>& y, const std::vector<double>& ref, size_t count);

// Log-spectral distance in dB: STFT of fftSize points (Hann, hop fftSize/4), bins up to maxHz,
// levels floored floorDb below the reference's peak, RMS over bins, mean over frames in the first
// `seconds` of signal.
double logSpectralDistance(const std::vector<double>& y, const std::vector<double>& ref, double rateHz,
                           double seconds = 1.0, double maxHz = 20000.0, double floorDb = 80.0, int fftSize = 2048);

// Frequency of the strongest spectral peak in [lowHz, highHz] of signal[begin, begin+count)
// (Hann window, zero-padded to at least 2^20 points, parabolic interpolation of the log magnitude).
double peakFrequency(const std::vector<double>& signal, double rateHz, double lowHz, double highHz, size_t begin = 0,
                     size_t count = 0);

// Power-weighted mean frequency of [lowHz, highHz] in signal[begin, begin+count) (Hann window).
double spectralCentroid(const std::vector<double>& signal, double rateHz, size_t begin, size_t count, double lowHz,
                        double highHz);

// |X(f)|^2 of a Hann-windowed segment zero-padded to fftSize (fftSize/2+1 bins).
std::vector<double> powerSpectrum(const double* segment, size_t count, size_t fftSize);

}  // namespace jawari
