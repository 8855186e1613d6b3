#include "offline/Analysis.h"

#include "offline/FftwPlanner.h"

#include <fftw3.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <memory>
#include <numbers>
#include <stdexcept>

namespace jawari
{
namespace
{
struct RealFft
{
    explicit RealFft(size_t n)
        : size(n)
    {
        time = fftw_alloc_real(n);
        freq = fftw_alloc_complex(n / 2 + 1);
        std::lock_guard<std::mutex> lock(fftwPlannerMutex());
        forward = fftw_plan_dft_r2c_1d(int(n), time, freq, FFTW_ESTIMATE);
        backward = fftw_plan_dft_c2r_1d(int(n), freq, time, FFTW_ESTIMATE);
    }
    ~RealFft()
    {
        {
            std::lock_guard<std::mutex> lock(fftwPlannerMutex());
            fftw_destroy_plan(forward);
            fftw_destroy_plan(backward);
        }
        fftw_free(time);
        fftw_free(freq);
    }
    RealFft(const RealFft&) = delete;
    RealFft& operator=(const RealFft&) = delete;
    size_t size;
    double* time;
    fftw_complex* freq;
    fftw_plan forward, backward;
};

double hann(size_t i, size_t n)
{
    return 0.5 - 0.5 * std::cos(2.0 * std::numbers::pi * double(i) / double(n));
}
}  // namespace

namespace
{
// The signal with each bin of its FFT multiplied by gain(frequency in Hz), real and even: a
// zero-phase filter (circular over the signal's length).
template <typename Gain>
std::vector<double> filteredByBins(const std::vector<double>& signal, double rateHz, Gain&& gain)
{
    const size_t n = signal.size();
    if (n == 0)
        return {};
    RealFft fft(n);
    std::copy(signal.begin(), signal.end(), fft.time);
    fftw_execute(fft.forward);
    for (size_t k = 0; k <= n / 2; ++k)
    {
        const double g = gain(double(k) * rateHz / double(n));
        if (g == 0.0)
            fft.freq[k][0] = fft.freq[k][1] = 0.0;
        else
        {
            fft.freq[k][0] *= g;
            fft.freq[k][1] *= g;
        }
    }
    fftw_execute(fft.backward);
    std::vector<double> out(fft.time, fft.time + n);
    for (double& v : out)
        v /= double(n);
    return out;
}
}  // namespace

std::vector<double> lowpass(const std::vector<double>& signal, double rateHz, double cutoffHz)
{
    return filteredByBins(signal, rateHz, [&](double f) { return f > cutoffHz ? 0.0 : 1.0; });
}

std::vector<double> zeroPhaseBand(const std::vector<double>& signal, double rateHz, double lowHz, double highHz,
                                  int order)
{
    const double n2 = 2.0 * order;
    return filteredByBins(signal, rateHz, [&](double f) {
        const double highPass = f > 0.0 ? 1.0 / (1.0 + std::pow(lowHz / f, n2)) : 0.0;
        const double lowPass = 1.0 / (1.0 + std::pow(f / highHz, n2));
        return highPass * lowPass;
    });
}

std::vector<double> precursorLeads(const std::vector<double>& signal, double rateHz, double f1, double seconds,
                                   double frameSeconds)
{
    auto bandEnergy = [&](double low, double high) {
        auto e = zeroPhaseBand(signal, rateHz, low * f1, high * f1);
        for (double& v : e)
            v *= v;
        return e;
    };
    const auto lowBand = bandEnergy(6.0, 12.0), highBand = bandEnergy(24.0, 48.0);
    const size_t frame = static_cast<size_t>(std::llround(frameSeconds * rateHz)), hop = frame / 2;
    const size_t end = std::min(signal.size(), static_cast<size_t>(std::llround(seconds * rateHz)));
    const double w1 = 2.0 * std::numbers::pi * f1 / rateHz, period = 1.0 / f1;
    // Where in the period a band's energy arrives: the phase of its component at f1.
    auto arrival = [&](const std::vector<double>& e, size_t begin) {
        std::complex<double> z;
        for (size_t i = 0; i < frame; ++i)
            z += hann(i, frame - 1) * e[begin + i] * std::polar(1.0, -w1 * double(begin + i));
        return -std::arg(z) / (2.0 * std::numbers::pi) * period;
    };
    std::vector<double> leads;
    for (size_t begin = 0; begin + frame <= end; begin += hop)
        leads.push_back(std::remainder(arrival(lowBand, begin) - arrival(highBand, begin), period));
    return leads;
}

double relativeL2(const std::vector<double>& y, const std::vector<double>& ref, size_t count)
{
    count = std::min({count, y.size(), ref.size()});
    double num = 0.0, den = 0.0;
    for (size_t i = 0; i < count; ++i)
    {
        num += (y[i] - ref[i]) * (y[i] - ref[i]);
        den += ref[i] * ref[i];
    }
    return den > 0.0 ? std::sqrt(num / den) : std::sqrt(num);
}

namespace
{
// One plan serves every frame of a measurement (planning per frame is slow, and two plans of the
// same size need not round identically).
std::vector<double> powerSpectrumWith(RealFft& fft, const double* segment, size_t count)
{
    const size_t fftSize = fft.size;
    std::fill(fft.time, fft.time + fftSize, 0.0);
    for (size_t i = 0; i < std::min(count, fftSize); ++i)
        fft.time[i] = segment[i] * hann(i, count);
    fftw_execute(fft.forward);
    std::vector<double> p(fftSize / 2 + 1);
    for (size_t k = 0; k < p.size(); ++k)
        p[k] = fft.freq[k][0] * fft.freq[k][0] + fft.freq[k][1] * fft.freq[k][1];
    return p;
}

// The power-weighted mean frequency of the bins of p within [lowHz, highHz] (0 when they hold none).
double bandCentroid(const std::vector<double>& p, double binHz, double lowHz, double highHz)
{
    double num = 0.0, den = 0.0;
    for (size_t k = 0; k < p.size(); ++k)
    {
        const double f = double(k) * binHz;
        if (f < lowHz || f > highHz)
            continue;
        num += f * p[k];
        den += p[k];
    }
    return den > 0.0 ? num / den : 0.0;
}
}  // namespace

std::vector<double> powerSpectrum(const double* segment, size_t count, size_t fftSize)
{
    RealFft fft(fftSize);
    return powerSpectrumWith(fft, segment, count);
}

double logSpectralDistance(const std::vector<double>& y, const std::vector<double>& ref, double rateHz, double seconds,
                           double maxHz, double floorDb, int fftSize)
{
    const size_t n = static_cast<size_t>(fftSize);
    const size_t hop = n / 4;
    const size_t length = std::min({y.size(), ref.size(), static_cast<size_t>(std::llround(seconds * rateHz))});
    if (length < n)
        throw std::invalid_argument("log-spectral distance needs at least one full frame");
    const size_t bins = std::min(n / 2, static_cast<size_t>(std::floor(maxHz * double(n) / rateHz)));

    std::vector<std::vector<double>> refFrames, yFrames;
    double peak = 0.0;
    RealFft fft(n);
    for (size_t start = 0; start + n <= length; start += hop)
    {
        refFrames.push_back(powerSpectrumWith(fft, ref.data() + start, n));
        yFrames.push_back(powerSpectrumWith(fft, y.data() + start, n));
        for (size_t k = 0; k <= bins; ++k)
            peak = std::max(peak, refFrames.back()[k]);
    }
    const double floorPower = peak * std::pow(10.0, -floorDb / 10.0);
    double total = 0.0;
    for (size_t f = 0; f < refFrames.size(); ++f)
    {
        double sum = 0.0;
        for (size_t k = 0; k <= bins; ++k)
        {
            // The level difference as the log of a ratio: exact 0 for equal levels (a difference
            // of two logs would not be, once the compiler fuses it into an FMA).
            const double d =
                10.0 * std::log10(std::max(yFrames[f][k], floorPower) / std::max(refFrames[f][k], floorPower));
            sum += d * d;
        }
        total += std::sqrt(sum / double(bins + 1));
    }
    return total / double(refFrames.size());
}

double peakFrequency(const std::vector<double>& signal, double rateHz, double lowHz, double highHz, size_t begin,
                     size_t count)
{
    if (count == 0)
        count = signal.size() - begin;
    size_t fftSize = 1 << 20;
    while (fftSize < 4 * count)
        fftSize *= 2;
    const auto p = powerSpectrum(signal.data() + begin, count, fftSize);
    const double binHz = rateHz / double(fftSize);
    const size_t lo = static_cast<size_t>(std::ceil(lowHz / binHz));
    const size_t hi = std::min(p.size() - 2, static_cast<size_t>(std::floor(highHz / binHz)));
    size_t best = lo;
    for (size_t k = lo; k <= hi; ++k)
        if (p[k] > p[best])
            best = k;
    const double a = std::log(p[best - 1] + 1e-300), b = std::log(p[best] + 1e-300), c = std::log(p[best + 1] + 1e-300);
    const double denom = a - 2.0 * b + c;
    const double offset = denom != 0.0 ? 0.5 * (a - c) / denom : 0.0;
    return (double(best) + offset) * binHz;
}

double spectralCentroid(const std::vector<double>& signal, double rateHz, size_t begin, size_t count, double lowHz,
                        double highHz)
{
    size_t fftSize = 1;
    while (fftSize < count)
        fftSize *= 2;
    return bandCentroid(powerSpectrum(signal.data() + begin, count, fftSize), rateHz / double(fftSize), lowHz, highHz);
}

namespace
{
// One plan per size, kept for the thread: two measures of the same signal must round alike.
RealFft& framePlan(size_t fftSize)
{
    thread_local std::vector<std::unique_ptr<RealFft>> plans;
    for (auto& plan : plans)
        if (plan->size == fftSize)
            return *plan;
    plans.push_back(std::make_unique<RealFft>(fftSize));
    return *plans.back();
}

// Hann-windowed frames of frameSeconds, hop half a frame, over the first `seconds`: each frame's
// power spectrum handed to `use` with the bin spacing.
template <typename Use>
void forEachFrame(const std::vector<double>& signal, double rateHz, double seconds, double frameSeconds, Use&& use)
{
    const size_t frame = static_cast<size_t>(std::llround(frameSeconds * rateHz));
    const size_t length = std::min(signal.size(), static_cast<size_t>(std::llround(seconds * rateHz)));
    if (frame < 16 || length < frame)
        throw std::invalid_argument("a frame-by-frame measure needs at least one full frame");
    size_t fftSize = 1;
    while (fftSize < frame)
        fftSize *= 2;
    RealFft& fft = framePlan(fftSize);
    const double binHz = rateHz / double(fftSize);
    for (size_t start = 0; start + frame <= length; start += frame / 2)
        use(powerSpectrumWith(fft, signal.data() + start, frame), binHz);
}
}  // namespace

BandEnvelope bandEnvelope(const std::vector<double>& signal, double rateHz, double seconds, double frameSeconds,
                          double maxHz)
{
    BandEnvelope e;
    const double edge = std::pow(2.0, 1.0 / 6.0);
    for (int k = -13;; ++k)  // 1 kHz x 2^(-13/3) = 49.6 Hz
    {
        const double centre = 1000.0 * std::pow(2.0, k / 3.0);
        if (centre * edge > std::min(maxHz, 0.5 * rateHz))
            break;
        e.centresHz.push_back(centre);
    }
    forEachFrame(signal, rateHz, seconds, frameSeconds, [&](const std::vector<double>& p, double binHz) {
        std::vector<double> levels(e.centresHz.size(), 0.0);
        for (size_t b = 0; b < levels.size(); ++b)
        {
            const double low = e.centresHz[b] / edge, high = e.centresHz[b] * edge;
            double energy = 0.0;
            for (size_t k = static_cast<size_t>(std::ceil(low / binHz)); k < p.size() && double(k) * binHz < high; ++k)
                energy += p[k];
            levels[b] = 10.0 * std::log10(std::max(energy, 1e-300));
        }
        e.levelsDb.push_back(std::move(levels));
    });
    return e;
}

double bandEnvelopeDistance(const std::vector<double>& y, const std::vector<double>& ref, double rateHz,
                            double seconds, double frameSeconds, double floorDb)
{
    const auto a = bandEnvelope(y, rateHz, seconds, frameSeconds), b = bandEnvelope(ref, rateHz, seconds, frameSeconds);
    double loudest = -1e300;
    for (const auto& frame : b.levelsDb)
        for (double v : frame)
            loudest = std::max(loudest, v);
    const double floor = loudest - floorDb;
    const size_t frames = std::min(a.levelsDb.size(), b.levelsDb.size());
    double sum = 0.0;
    size_t count = 0;
    for (size_t f = 0; f < frames; ++f)
        for (size_t k = 0; k < b.centresHz.size(); ++k)
        {
            const double d = std::max(a.levelsDb[f][k], floor) - std::max(b.levelsDb[f][k], floor);
            sum += d * d;
            ++count;
        }
    return count > 0 ? std::sqrt(sum / double(count)) : 0.0;
}

std::vector<double> centroidTrack(const std::vector<double>& signal, double rateHz, double lowHz, double highHz,
                                  double seconds, double frameSeconds)
{
    std::vector<double> track;
    forEachFrame(signal, rateHz, seconds, frameSeconds, [&](const std::vector<double>& p, double binHz) {
        track.push_back(bandCentroid(p, binHz, lowHz, highHz));
    });
    return track;
}

double centroidTrackDistance(const std::vector<double>& y, const std::vector<double>& ref, double rateHz,
                             double lowHz, double highHz, double seconds, double frameSeconds)
{
    const auto a = centroidTrack(y, rateHz, lowHz, highHz, seconds, frameSeconds);
    const auto b = centroidTrack(ref, rateHz, lowHz, highHz, seconds, frameSeconds);
    double sum = 0.0;
    size_t count = 0;
    for (size_t f = 0; f < std::min(a.size(), b.size()); ++f)
        if (b[f] > 0.0)
        {
            const double d = a[f] / b[f] - 1.0;
            sum += d * d;
            ++count;
        }
    return count > 0 ? std::sqrt(sum / double(count)) : 0.0;
}

AccuracyFigures accuracyFigures(const std::vector<double>& y, const std::vector<double>& ref, double rateHz,
                                double buzzFromHz, double seconds)
{
    return {relativeL2(y, ref, static_cast<size_t>(std::llround(0.1 * rateHz))),
            logSpectralDistance(y, ref, rateHz, seconds), bandEnvelopeDistance(y, ref, rateHz, seconds),
            centroidTrackDistance(y, ref, rateHz, buzzFromHz, 20000.0, seconds)};
}

}  // namespace jawari
