// The output resampler (libsoxr): aligned in time and flat in the audio band.

#include "offline/Resampler.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>

using namespace jawari;

TEST_CASE("resampling 2 MHz to 48 kHz keeps a 1 kHz and a 15 kHz tone exact in time and level")
{
    for (double f : {1000.0, 15000.0})
    {
        const double in = 2e6, out = 48000.0;
        std::vector<double> x(2000000);
        for (size_t n = 0; n < x.size(); ++n)
            x[n] = std::sin(2.0 * std::numbers::pi * f * double(n) / in);
        Resampler r(in, out);
        std::vector<double> y;
        for (size_t i = 0; i < x.size(); i += 4096)
            r.push(x.data() + i, std::min<size_t>(4096, x.size() - i), y);
        r.finish(y);
        REQUIRE(y.size() == 48000);
        double worst = 0.0;
        for (size_t m = 4800; m < 43200; ++m)  // away from the edges of the finite signal
            worst = std::max(worst, std::abs(y[m] - std::sin(2.0 * std::numbers::pi * f * double(m) / out)));
        INFO(f << " Hz: worst error " << worst);
        CHECK(worst < 1e-4);
    }
}

TEST_CASE("resampling removes what lies above the output Nyquist frequency")
{
    const double in = 2e6, out = 48000.0, f = 30000.0;  // would alias to 18 kHz
    std::vector<double> x(400000);
    for (size_t n = 0; n < x.size(); ++n)
        x[n] = std::sin(2.0 * std::numbers::pi * f * double(n) / in);
    Resampler r(in, out);
    std::vector<double> y;
    r.push(x.data(), x.size(), y);
    r.finish(y);
    double peak = 0.0;
    for (size_t m = 1000; m + 1000 < y.size(); ++m)
        peak = std::max(peak, std::abs(y[m]));
    INFO("residual of a 30 kHz tone: " << 20 * std::log10(peak) << " dB");
    CHECK(peak < 1e-5);  // at least 100 dB down
}
