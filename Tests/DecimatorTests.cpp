// The voice's decimator, measured by running tones through it (docs/design.md section 2), against
// its specification: flat to 20 kHz within 0.1 dB at 48 kHz, aliasing at least 90 dB down, latency stated.

#include "realtime/voice/Decimator.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <vector>

using namespace jawari;

namespace
{
// Runs a unit tone of frequency f through the decimator. Returns the largest difference between
// output k and the tone at t = (k - latency) / host rate (so gain and timing are both checked: a
// fraction of a host sample off shows at 20 kHz as a deviation of order 1), and the output's peak
// (for tones that must not come through).
struct Measured
{
    double worstDeviation = 0.0;
    double peak = 0.0;
};

Measured run(Decimator& d, double hostRate, double f)
{
    d.reset();
    const int factor = d.factor();
    const double rate = factor * hostRate;
    const int hostSamples = d.length() / factor + 4096;
    std::vector<double> block(factor);
    Measured m;
    for (int k = 0; k < hostSamples; ++k)
    {
        for (int i = 0; i < factor; ++i)
            block[i] = std::sin(2.0 * std::numbers::pi * f * double(k * factor + i) / rate);
        const double y = d.process(block.data());
        if (k < hostSamples - 2048)
            continue;
        // Output k stands for the signal at t = (k - latency) / host rate, the internal sample
        // (k - latency) * factor: the reference's output k - latency.
        const double t = double(k - d.latencyHostSamples()) / hostRate;
        m.worstDeviation = std::max(m.worstDeviation, std::abs(y - std::sin(2.0 * std::numbers::pi * f * t)));
        m.peak = std::max(m.peak, std::abs(y));
    }
    return m;
}
}  // namespace

TEST_CASE("decimator is flat within 0.1 dB to 20 kHz with aliases at least 90 dB down and the stated latency")
{
    for (double host : {44100.0, 48000.0, 96000.0})
        for (int factor : {2, 4, 8, 16, 64})
        {
            Decimator d(factor, host);
            // 0.1 dB is 1.16 % of amplitude; the deviation bounds gain and delay error together.
            double worstPass = 0.0, worstAliasDb = -400.0;
            for (double f = 50.0; f <= d.passbandHz(); f += d.passbandHz() / 31.0)
                worstPass = std::max(worstPass, run(d, host, f).worstDeviation);
            // Everything between the host and the internal Nyquist frequencies would fold back.
            const double internalNyquist = 0.5 * factor * host;
            for (double f = 0.5 * host; f < internalNyquist; f += (internalNyquist - 0.5 * host) / 53.0)
                worstAliasDb = std::max(worstAliasDb, 20.0 * std::log10(run(d, host, f).peak + 1e-300));
            INFO("host " << host << " factor " << factor << ": " << d.length() << " taps, latency "
                         << d.latencyHostSamples() << " host samples, passband to " << d.passbandHz()
                         << " Hz, worst deviation " << worstPass << ", worst alias " << worstAliasDb << " dB");
            CHECK(worstPass < 1e-4);  // far inside 0.1 dB (1.16e-2)
            CHECK(worstAliasDb < -90.0);
        }
}

TEST_CASE("decimator by 1 is a pass-through without latency")
{
    Decimator d(1, 48000.0);
    const double x = 0.25;
    CHECK(d.process(&x) == 0.25);
    CHECK(d.latencyHostSamples() == 0);
}
