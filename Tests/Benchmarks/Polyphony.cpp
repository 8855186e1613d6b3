// The instrument's cost against the number of sounding strings: 1, 2, 4, 8 and 12 strings (up to
// eight held notes, then the drone's four) at draft, standard and high, on the tanpura bridge (the Default
// structure: a point bridge at x = 6 mm), 48 kHz in 512-sample blocks, one core. Reports the load
// (CPU time over audio time, mean and worst block) and the real-time factor per string (the
// instrument's real-time factor times its string count), with the strings stepped each alone and by
// the string bank. Measures and reports; never asserts.
// Writes CSV: quality, scheduling, strings, mean_load, worst_load, realtime_factor_per_string.
//
//   jawari-polyphony [out.csv] [--seconds S] [--method realtime|quadratised|penalty|spline]
//   jawari-polyphony --bank-sweep [--seconds S]   twelve strings at standard: lone voices against the
//                                                 bank in each group size, lanes or scalar solves

#include "offline/CpuClock.h"
#include "realtime/instrument/Instrument.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

using namespace jawari;

namespace
{
struct Load
{
    double mean = 0.0, worst = 0.0;
};

// Plays `strings` strings for `seconds`: held notes C3 up in whole tones, the drone beyond eight.
ContactMethod gMethod = InstrumentStructure{}.method;  // --method: every measurement's contact method

struct Scheduling
{
    StringScheduling kind = StringScheduling::lone;
    int group = StringBank::kMaxStrings;
    StringBank::Solve solve = StringBank::Solve::lanes;
};

Load measure(int quality, Scheduling scheduling, int strings, double seconds)
{
    constexpr double rate = 48000.0;
    constexpr int block = 512;
    InstrumentStructure structure;
    structure.quality = quality;
    structure.method = gMethod;
    structure.obstaclePosition = 0.006;
    auto pack = buildVoicePack(structure);
    Instrument instrument;
    instrument.setScheduling(scheduling.kind);
    instrument.bank().configure(scheduling.group, scheduling.solve);
    InstrumentControls controls;
    controls.drone = strings > kMidiVoices;
    controls.droneTempo = 200.0;  // the four drone strings all sounding within a second
    controls.humanise = 0.0;
    instrument.setControls(controls);
    instrument.install(pack.get(), nullptr);
    for (int i = 0; i < std::min(strings, kMidiVoices); ++i)
        instrument.noteOn(48 + 2 * i, 0.8);
    std::vector<float> left(block), right(block);
    const int blocks = static_cast<int>(seconds * rate / block);
    const double budget = block / rate;
    double total = 0.0, worst = 0.0;
    for (int b = 0; b < blocks; ++b)
    {
        if (b % 94 == 93)  // every second: the held notes plucked again, so they keep sounding
            for (int i = 0; i < std::min(strings, kMidiVoices); ++i)
                instrument.noteOn(48 + 2 * i, 0.8);
        const double start = threadCpuSeconds();
        instrument.render(left.data(), right.data(), block);
        const double spent = threadCpuSeconds() - start;
        total += spent;
        worst = std::max(worst, spent);
    }
    return {total / (blocks * budget), worst / budget};
}
}  // namespace

int main(int argc, char** argv)
{
    const char* path = nullptr;
    double seconds = 5.0;
    bool sweep = false;
    for (int i = 1; i < argc; ++i)
    {
        if (std::strcmp(argv[i], "--bank-sweep") == 0)
            sweep = true;
        else if (std::strcmp(argv[i], "--method") == 0 && i + 1 < argc)
        {
            const auto method = contactMethodFromSceneName(argv[++i]);
            if (!method)
            {
                std::fprintf(stderr, "jawari-polyphony: --method: realtime, quadratised, penalty or spline\n");
                return 2;
            }
            gMethod = *method;
        }
        else if (std::strcmp(argv[i], "--seconds") == 0 && i + 1 < argc)
            seconds = std::atof(argv[++i]);
        else if (argv[i][0] == '-' || path != nullptr)
        {
            std::fprintf(stderr, "jawari-polyphony: unknown option or second file '%s'\n", argv[i]);
            return 2;
        }
        else
            path = argv[i];
    }
    if (!(seconds > 0.0))
    {
        std::fprintf(stderr, "jawari-polyphony: --seconds must be a positive number\n");
        return 2;
    }
    if (sweep)
    {
        const Load lone = measure(1, {}, 12, seconds);
        std::printf("12 strings, standard: lone voices: mean %5.1f %%, worst block %5.1f %%\n", 100.0 * lone.mean,
                    100.0 * lone.worst);
        for (const auto solve : {StringBank::Solve::lanes, StringBank::Solve::scalar})
            for (int group : {1, 2, 3, 4, 6, 12})
            {
                const Load load = measure(1, {StringScheduling::bank, group, solve}, 12, seconds);
                std::printf("12 strings, standard: bank, groups of %2d, %s solves: mean %5.1f %%, worst block %5.1f %%\n",
                            group, solve == StringBank::Solve::lanes ? "lanes " : "scalar", 100.0 * load.mean,
                            100.0 * load.worst);
                std::fflush(stdout);
            }
        return 0;
    }
    FILE* out = path != nullptr ? std::fopen(path, "w") : stdout;
    if (out == nullptr)
    {
        std::fprintf(stderr, "jawari-polyphony: cannot write %s\n", path);
        return 1;
    }
    std::fprintf(out, "quality,scheduling,strings,mean_load,worst_load,realtime_factor_per_string\n");
    for (int q = 0; q < 3; ++q)  // draft, standard and high
        for (int strings : {1, 2, 4, 8, 12})
            for (const auto scheduling : {StringScheduling::lone, StringScheduling::bank})
            {
                const char* name = scheduling == StringScheduling::bank ? "bank" : "lone";
                const Load load = measure(q, {scheduling}, strings, seconds);
                std::fprintf(out, "%s,%s,%d,%.4f,%.4f,%.4g\n", kQualitySettings[q].name, name, strings, load.mean,
                             load.worst, strings / load.mean);
                std::fflush(out);
                std::fprintf(stderr,
                             "%-8s %s %2d strings: mean %5.1f %%, worst block %5.1f %%, %6.1fx real time per string\n",
                             kQualitySettings[q].name, name, strings, 100.0 * load.mean, 100.0 * load.worst,
                             strings / load.mean);
            }
    return 0;
}
