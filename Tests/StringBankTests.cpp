// The string bank (realtime/instrument/StringBank.h): strings stepped together, their contact solves in SIMD
// lanes, give what each string gives alone, and each lane keeps the scheme's energy balance.

#include "TestSupport.h"
#include "realtime/instrument/Instrument.h"
#include "realtime/instrument/StringBank.h"

#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <memory>
#include <vector>

using namespace jawari;

namespace
{
constexpr int kStrings = 12;
constexpr int kChunk = 32;  // host samples per call, as the instrument renders

// What a player does to the twelve strings of a pack, chunk by chunk: notes start at their pitches
// (a pulse, or from a shape), some are released, one is stolen (silenced and plucked again), one is
// bent, the obstacle is raised. Applied identically to two packs.
void playScript(VoicePack& pack, int chunk)
{
    auto& voices = pack.voices;
    for (int i = 0; i < kStrings; ++i)
    {
        auto& v = *voices[size_t(i)];
        if (chunk == 0 || (chunk == 12 && i % 4 == 1))
        {
            const double ratio = std::pow(2.0, (i - 4) / 7.0);
            v.retune(ratio, v.solver().sigma().data());
            if (i % 3 == 0)
                v.pluckFromShape(1e-3);
            else
                v.pluckWithPulse(0.3 + 0.05 * i);
        }
        if (chunk == 8 && i % 3 == 2)
            v.release();
        if (chunk == 16 && i == 5)
        {
            v.silence();
            v.pluckWithPulse(0.9);
        }
        if (chunk >= 20 && chunk < 24 && i == 7)
            v.retune(v.tuningRatio() * 1.01, v.solver().sigma().data());
        if (chunk == 26)
            v.setContactLaw({1e12, 1.3}, 1e-4);
    }
}

struct Difference
{
    double worst = 0.0;  // max |bank - lone| / max |lone|, over the strings
    double peak = 0.0;
    long contactSteps = 0;
};

Difference bankAgainstLone(ObstacleShape shape)
{
    const InstrumentStructure structure = test::scriptStructure(shape);
    auto lone = buildVoicePack(structure);
    auto banked = buildVoicePack(structure);
    const int os = lone->oversampling;
    std::vector<std::vector<double>> loneOut(kStrings, std::vector<double>(size_t(kChunk * os)));
    std::vector<std::vector<double>> bankOut = loneOut;
    std::array<Voice*, kStrings> voices{};
    std::array<double*, kStrings> outs{};
    for (int i = 0; i < kStrings; ++i)
    {
        voices[size_t(i)] = banked->voices[size_t(i)].get();
        outs[size_t(i)] = bankOut[size_t(i)].data();
    }
    StringBank bank;
    Difference d;
    std::vector<double> peak(kStrings, 0.0), worst(kStrings, 0.0);
    for (int chunk = 0; chunk < 40; ++chunk)
    {
        playScript(*lone, chunk);
        playScript(*banked, chunk);
        for (int i = 0; i < kStrings; ++i)
            lone->voices[size_t(i)]->processInternal(loneOut[size_t(i)].data(), kChunk);
        bank.process(voices.data(), outs.data(), kStrings, kChunk);
        for (int i = 0; i < kStrings; ++i)
        {
            d.contactSteps += lone->voices[size_t(i)]->takeIterationCount() > 0 ? 1 : 0;
            for (int k = 0; k < kChunk * os; ++k)
            {
                peak[size_t(i)] = std::max(peak[size_t(i)], std::abs(loneOut[size_t(i)][size_t(k)]));
                worst[size_t(i)] = std::max(worst[size_t(i)],
                                            std::abs(bankOut[size_t(i)][size_t(k)] - loneOut[size_t(i)][size_t(k)]));
            }
        }
    }
    for (int i = 0; i < kStrings; ++i)
    {
        d.worst = std::max(d.worst, worst[size_t(i)] / peak[size_t(i)]);
        d.peak = std::max(d.peak, peak[size_t(i)]);
    }
    return d;
}
}  // namespace

TEST_CASE("The string bank gives each string what it gives alone, to 1e-12, on each obstacle shape")
{
    for (const auto shape : {ObstacleShape::point, ObstacleShape::parabola, ObstacleShape::frets})
    {
        const Difference d = bankAgainstLone(shape);
        INFO("shape " << int(shape) << ": worst relative difference " << d.worst << ", peak " << d.peak
                      << ", string-chunks with Newton iterations " << d.contactSteps);
        CHECK(d.peak > 1e-5);
        CHECK(d.contactSteps > 100);  // the strings touch the obstacle
        CHECK(d.worst <= 1e-12);
    }
}

TEST_CASE("Each lane of the string bank conserves energy without losses and never gains it with them")
{
    // Twelve strings of the paper's string on one point obstacle, at different pitches and pluck
    // amplitudes, so the lanes touch at different times.
    for (const bool lossless : {true, false})
    {
        VoiceConfig config;
        config.string = test::paperString(lossless ? DampingLaw::none : DampingLaw::valette);
        config.obstacles = {test::pointObstacle(0.006, 0.0)};
        config.modes = 100;
        config.oversampling = 8;
        config.residualCompliance = false;
        std::vector<std::unique_ptr<Voice>> voices;
        std::array<Voice*, kStrings> pointers{};
        std::vector<std::vector<double>> out(kStrings, std::vector<double>(size_t(config.oversampling)));
        std::array<double*, kStrings> outs{};
        std::vector<double> start(kStrings), previous(kStrings);
        for (int i = 0; i < kStrings; ++i)
        {
            voices.push_back(std::make_unique<Voice>(config));
            auto& v = *voices.back();
            std::vector<double> sigma(size_t(v.modes()), 0.0);
            if (!lossless)
                sigma = v.solver().sigma();
            v.retune(std::pow(2.0, i / 12.0), sigma.data());
            v.setInitialShape(0.3 + 0.02 * i, (0.5 + 0.1 * i) * 1e-3);
            pointers[size_t(i)] = &v;
            outs[size_t(i)] = out[size_t(i)].data();
            start[size_t(i)] = previous[size_t(i)] = v.solver().energy().total;
        }
        StringBank bank;
        double worstDrift = 0.0, worstRise = 0.0;
        long contactSteps = 0;
        for (int n = 0; n < 2000; ++n)  // 2000 host samples, 16000 steps
        {
            bank.process(pointers.data(), outs.data(), kStrings, 1);
            for (int i = 0; i < kStrings; ++i)
            {
                auto& v = *pointers[size_t(i)];
                contactSteps += v.takeIterationCount() > 0 ? 1 : 0;
                const double H = v.solver().energy().total;
                worstDrift = std::max(worstDrift, std::abs(H - start[size_t(i)]) / start[size_t(i)]);
                worstRise = std::max(worstRise, (H - previous[size_t(i)]) / start[size_t(i)]);
                previous[size_t(i)] = H;
            }
        }
        INFO((lossless ? "lossless" : "lossy") << ": worst relative drift " << worstDrift << ", worst rise "
                                               << worstRise << ", host samples with contact " << contactSteps);
        CHECK(contactSteps > 1000);
        if (lossless)
            CHECK(worstDrift <= 1e-9);
        else
        {
            CHECK(worstDrift > 1e-3);  // the losses are real
            CHECK(worstRise <= 1e-12);
        }
    }
}
