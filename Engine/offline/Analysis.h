#pragma once
// Signal measures for accuracy (docs/design.md section 4) and for the physics tests. OFF.

#include <cstddef>
#include <vector>

namespace jawari
{

// Ideal low-pass by FFT: every bin above cutoffHz set to zero.
std::vector<double> lowpass(const std::vector<double>& signal, double rateHz, double cutoffHz);

// Zero-phase band-pass by FFT: each bin weighted by |H|^2 of an order-`order` Butterworth high-pass
// at lowHz and low-pass at highHz, what running the pair forwards and backwards gives.
std::vector<double> zeroPhaseBand(const std::vector<double>& signal, double rateHz, double lowHz, double highHz,
                                  int order = 4);

// The dispersion precursor of a stiff string against its bridge (DAFx-16, their Fig. 7): per frame
// of frameSeconds (Hann, hop half a frame, over the first `seconds`), how much earlier in each
// period 1/f1 the energy of the band [24, 48] f1 arrives than that of [6, 12] f1 (s, wrapped to
// +-1/(2 f1)). Each band's energy is its zero-phase band-pass squared; where it arrives is the phase
// of its component at f1. Stiffness makes high partials travel faster, so they lead (> 0); a string
// without stiffness rings after each edge instead (<= 0).
std::vector<double> precursorLeads(const std::vector<double>& signal, double rateHz, double f1, double seconds = 1.2,
                                   double frameSeconds = 0.1);

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

// What a listener hears, without punishing a rattle that went the other way (docs/design.md
// section 4): the time-varying spectral envelope, energy per third-octave band (centres
// 1 kHz x 2^(k/3) from 50 Hz up to the last band below maxHz) per frame of frameSeconds
// (Hann window, hop half a frame), in dB. levelsDb[frame][band].
struct BandEnvelope
{
    std::vector<double> centresHz;
    std::vector<std::vector<double>> levelsDb;
};
BandEnvelope bandEnvelope(const std::vector<double>& signal, double rateHz, double seconds = 1.0,
                          double frameSeconds = 0.05, double maxHz = 20000.0);

// RMS over bands and frames of the envelopes' level difference in dB, both floored floorDb below
// the reference's loudest band in any frame, over the first `seconds`.
double bandEnvelopeDistance(const std::vector<double>& y, const std::vector<double>& ref, double rateHz,
                            double seconds = 1.0, double frameSeconds = 0.05, double floorDb = 60.0);

// The power-weighted mean frequency of [lowHz, highHz] per frame (Hann, hop half a frame) over the
// first `seconds`: the buzz band's centroid as it moves (lowHz at the 10th partial for a jawari).
std::vector<double> centroidTrack(const std::vector<double>& signal, double rateHz, double lowHz, double highHz,
                                  double seconds = 1.0, double frameSeconds = 0.05);

// RMS over frames of the relative difference of two centroid tracks, c_y / c_ref - 1.
double centroidTrackDistance(const std::vector<double>& y, const std::vector<double>& ref, double rateHz,
                             double lowHz, double highHz, double seconds = 1.0, double frameSeconds = 0.05);

// Every accuracy measure of y against ref (docs/design.md section 4): relL2 over the first 100 ms,
// LSD, band envelope and the centroid track of the buzz band from buzzFromHz to 20 kHz over the
// first `seconds`. Both signals already low-passed at 20 kHz.
struct AccuracyFigures
{
    double relL2 = 0.0, lsd = 0.0, envelope = 0.0, centroid = 0.0;
};
AccuracyFigures accuracyFigures(const std::vector<double>& y, const std::vector<double>& ref, double rateHz,
                                double buzzFromHz, double seconds = 1.0);

// |X(f)|^2 of a Hann-windowed segment zero-padded to fftSize (fftSize/2+1 bins).
std::vector<double> powerSpectrum(const double* segment, size_t count, size_t fftSize);

}  // namespace jawari
