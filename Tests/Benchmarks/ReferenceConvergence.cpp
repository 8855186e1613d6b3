// Refinement study of the reference solver (issue 28): one scene rendered by the reference at a
// ladder of configurations, each knob refined alone from the base (1001 modes, 2 MHz, contact
// points on the base grid, L/1002 apart) and all together, and every successive pair compared.
//
//   modes    M = 1001, 2003, 4001             (2 MHz, spacing L/1002: every 1st, 2nd, 4th node)
//   rate     2, 4, 8, 16 MHz                  (1001 modes, spacing L/1002)
//   spacing  L/1002, L/2004, L/4008           (1001 modes, 2 MHz: off the grid past the first rung,
//                                              so the projection path, O(M P) a step)
//   all      (1001, 2 MHz, L/1002), (2003, 4 MHz, L/2004), (4001, 8 MHz, L/4002),
//            (4001, 16 MHz, L/4002)           (contact points on the solver's own grid)
//   modes-fine  M = 1001, 2003, 4001 at L/16032 (2 MHz: the points never coarser than the modes)
//   joint    (1001, 2 MHz), (2003, 8 MHz), (4001, 32 MHz) at L/16032 (+(8003, 128 MHz) with --extend):
//            the rate grows as M^2, as the stiff string's top mode does
//   extrapolated  (1001, 8 MHz), (2003, 16 MHz), (4001, 32 MHz) at L/16032, each the rate extrapolated:
//            rendered at R and 2R, 2 y(2R) - y(R) (a scene's "extrapolate_rate"), which cancels an
//            error first order in the step (a contact shorter than it); (8003, 64 MHz) with --extend
//   static-modes, static-rate, static-spacing  the static-exact forcing from (2003, 2 MHz, L/16032):
//            M = 1001, 2003, 4001 at 4 MHz; 1, 2, 4, 8 MHz; L/8016 to L/64128
//
// Per pair, with the finer rung as the reference, both outputs low-passed at 20 kHz (as in
// jawari-accuracy): relL2 over the first 100 ms (or the whole render if shorter), and the
// log-spectral distance over the render (Analysis.h: Hann, hop N/4, bins to 20 kHz, floor 80 dB
// below the reference's peak) with N = 2048 (the project's measure; 6 frames over 100 ms at
// 48 kHz) and N = 1024 (15 frames, 47 Hz bins), so a distance carried by one frame shows.
// The floor row: the base against itself with the pluck's amplitude raised by 1e-4.
// CSV to stdout, one row per render (CPU seconds, one core) and per pair; progress to stderr.
// --cache DIR keeps every render's output, so a long study can run in chunks. --ladder adds a
// ladder of its own (modes:rate:intervals per rung, with ":x" the rate extrapolated, ":s" the static-exact
// forcing, ":xs" both); --knobs "" runs only it. The renders a study
// needs run side by side, one a core (--jobs N, every core by default); the rows come out in order.
//
//   jawari-convergence [--scene FILE] [--duration S] [--knobs modes,rate,spacing,all,modes-fine,joint,extrapolated,
//                                                            static-modes,static-rate,static-spacing]
//                      [--rungs N] [--ladder M:RATE:N[:x|:s|:xs],...] [--cache DIR] [--no-floor] [--extend] [--quick]
//                      [--jobs N]

#include "offline/Analysis.h"
#include "offline/CpuClock.h"
#include "offline/OfflineRender.h"
#include "offline/Scene.h"
#include "physics/contact/Obstacle.h"

#include "ConvergenceLadders.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

using namespace jawari;

namespace
{

using namespace jawari::convergence;

// One render's output and what it cost.
struct Rendered
{
    std::vector<double> output;  // 48 kHz (the scene's output rate), low-passed at 20 kHz
    double cpuSeconds = 0.0;
    int newtonMax = 0;
    double penetration = 0.0;
    bool transform = false;
    bool cached = false;
};

// The scene at a rung: the reference, the study's duration, every distributed obstacle's contact
// points L / intervals apart, the pluck scaled.
Scene sceneAt(const Scene& base, const Rung& r, double duration, double amplitudeScale)
{
    Scene s = base;
    s.simulation.reference = true;
    s.simulation.extrapolateRate = false;  // the rung decides (an extrapolated rung combines two plain renders)
    s.simulation.durationSeconds = duration;
    s.simulation.modes = r.modes;
    s.simulation.rateHz = r.rateHz;
    s.simulation.staticExactForcing = r.staticExact;
    s.excitation.amplitude *= amplitudeScale;
    for (auto& o : s.obstacles)
        if (o.isDistributed())
            o.spacing = s.string.lengthMetres / r.intervals;
    return s;
}

std::string cacheName(const std::string& sceneStem, const Rung& r, double duration, double amplitudeScale)
{
    char text[256];
    std::snprintf(text, sizeof text, "%s-d%g-M%d-R%.0f-N%d-a%.17g%s%s.bin", sceneStem.c_str(), duration, r.modes,
                  r.rateHz, r.intervals, amplitudeScale, r.extrapolated ? "-x" : "", r.staticExact ? "-s" : "");
    return text;
}

// The two plain renders an extrapolated rung combines: at its rate and at twice it.
std::pair<Rung, Rung> extrapolatedParts(const Rung& r)
{
    const Rung low{r.modes, r.rateHz, r.intervals, false, r.staticExact};
    return {low, Rung{r.modes, 2.0 * r.rateHz, r.intervals, false, r.staticExact}};
}

// The plain renders that the wanted (rung, pluck scale) pairs need: an extrapolated rung's two parts.
std::vector<std::pair<Rung, double>> plainRenders(const std::vector<std::pair<Rung, double>>& wanted)
{
    std::vector<std::pair<Rung, double>> plain;
    for (const auto& [r, scale] : wanted)
    {
        if (!r.extrapolated)
        {
            plain.emplace_back(r, scale);
            continue;
        }
        const auto [low, high] = extrapolatedParts(r);
        plain.emplace_back(low, scale);
        plain.emplace_back(high, scale);
    }
    return plain;
}

// The cache file: cpu seconds, newton max, penetration, transform flag, sample count, samples.
bool readCache(const std::string& path, Rendered& out)
{
    FILE* f = std::fopen(path.c_str(), "rb");
    if (f == nullptr)
        return false;
    double head[5] = {};
    bool ok = std::fread(head, sizeof(double), 5, f) == 5 && head[4] >= 0.0;
    if (ok)
    {
        out.output.resize(static_cast<size_t>(head[4]));
        ok = std::fread(out.output.data(), sizeof(double), out.output.size(), f) == out.output.size();
    }
    std::fclose(f);
    out.cpuSeconds = head[0];
    out.newtonMax = static_cast<int>(head[1]);
    out.penetration = head[2];
    out.transform = head[3] != 0.0;
    out.cached = ok;
    return ok;
}

void writeCache(const std::string& path, const Rendered& r)
{
    FILE* f = std::fopen(path.c_str(), "wb");
    if (f == nullptr)
        return;
    const double head[5] = {r.cpuSeconds, double(r.newtonMax), r.penetration, r.transform ? 1.0 : 0.0,
                            double(r.output.size())};
    std::fwrite(head, sizeof(double), 5, f);
    std::fwrite(r.output.data(), sizeof(double), r.output.size(), f);
    std::fclose(f);
}

// The scene file's name and a hash of its text (FNV-1a, 32 bits): a cached render of an edited scene
// is never taken for the new one's.
std::string cacheStem(const std::string& scenePath)
{
    std::ifstream file(scenePath, std::ios::binary);
    const std::string text((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
    uint32_t hash = 2166136261u;
    for (unsigned char c : text)
        hash = (hash ^ c) * 16777619u;
    char tag[16];
    std::snprintf(tag, sizeof tag, "-%08x", hash);
    return std::filesystem::path(scenePath).stem().string() + tag;
}

class Study
{
public:
    Study(const Options& options, Scene base)
        : options_(options)
        , base_(std::move(base))
        , stem_(std::filesystem::path(options.scenePath).stem().string())
        , cacheStem_(cacheStem(options.scenePath))
    {
    }

    // Renders every (rung, pluck scale) not yet in memory or in the cache, `jobs` at a time, each
    // on its own thread (renderScene shares nothing but the FFTW planner, which is locked).
    void prefetch(const std::vector<std::pair<Rung, double>>& wanted, unsigned jobs)
    {
        struct Job
        {
            Rung rung;
            double scale;
            std::string name;
        };
        std::vector<Job> missing;
        for (const auto& [r, scale] : plainRenders(wanted))
        {
            std::string name = cacheName(cacheStem_, r, options_.duration, scale);
            Rendered out;
            if (done_.count(name) != 0
                || std::any_of(missing.begin(), missing.end(), [&](const Job& j) { return j.name == name; }))
                continue;
            if (readCache(cachePath(name), out))
                done_.emplace(name, Entry{std::move(out)});
            else
                missing.push_back({r, scale, std::move(name)});
        }
        // The dearest first (modes x rate), so that the last one to finish is a cheap one.
        std::stable_sort(missing.begin(), missing.end(), [](const Job& a, const Job& b) {
            return a.rung.modes * a.rung.rateHz > b.rung.modes * b.rung.rateHz;
        });
        std::vector<Rendered> outputs(missing.size());
        std::mutex progress;
        size_t next = 0;
        auto worker = [&] {
            for (;;)
            {
                size_t k;
                {
                    std::lock_guard<std::mutex> lock(progress);
                    if (next == missing.size())
                        return;
                    k = next++;
                    std::fprintf(stderr, "rendering %s\n", missing[k].name.c_str());
                }
                renderNow(sceneAt(base_, missing[k].rung, options_.duration, missing[k].scale), outputs[k]);
            }
        };
        std::vector<std::thread> pool;
        for (unsigned j = 0; j < std::min<size_t>(jobs, missing.size()); ++j)
            pool.emplace_back(worker);
        for (auto& t : pool)
            t.join();
        for (size_t k = 0; k < missing.size(); ++k)
        {
            writeCache(cachePath(missing[k].name), outputs[k]);
            done_.emplace(missing[k].name, Entry{std::move(outputs[k])});
        }
    }

    // The rung's render (rendered now if no prefetch brought it), its row printed the first time.
    const Rendered& render(const Rung& r, double amplitudeScale = 1.0)
    {
        const std::string name = cacheName(cacheStem_, r, options_.duration, amplitudeScale);
        if (done_.count(name) == 0 && r.extrapolated)
            done_.emplace(name, Entry{extrapolate(r, amplitudeScale)});
        if (done_.count(name) == 0)
            prefetch({{r, amplitudeScale}}, 1);
        Entry& entry = done_.at(name);
        if (!entry.printed)
            printRender(r, amplitudeScale, entry.rendered);
        entry.printed = true;
        return entry.rendered;
    }

    // y against the finer (or unperturbed) ref: relL2 over 100 ms, LSD at 2048 and 1024 points.
    void printPair(const char* kind, const char* ladder, const Rung& coarse, const Rung& fine, const Rendered& y,
                   const Rendered& ref) const
    {
        if (y.output.empty() || ref.output.empty())
        {
            std::printf("%s,%s,%s,%d,%.0f,%d,,,,,,%d,%.0f,%d,nan,nan,nan\n", kind, stem_.c_str(), ladder, fine.modes,
                        fine.rateHz, fine.intervals, coarse.modes, coarse.rateHz, coarse.intervals);
            return;
        }
        const double rate = base_.simulation.outputRateHz;
        const size_t n = std::min(ref.output.size(), static_cast<size_t>(std::llround(0.1 * rate)));
        const double l2 = relativeL2(y.output, ref.output, n);
        const double lsd2048 = logSpectralDistance(y.output, ref.output, rate, options_.duration, 20000.0, 80.0, 2048);
        const double lsd1024 = logSpectralDistance(y.output, ref.output, rate, options_.duration, 20000.0, 80.0, 1024);
        std::printf("%s,%s,%s,%d,%.0f,%d,,,,,,%d,%.0f,%d,%.4g,%.4g,%.4g\n", kind, stem_.c_str(), ladder, fine.modes,
                    fine.rateHz, fine.intervals, coarse.modes, coarse.rateHz, coarse.intervals, l2, lsd2048, lsd1024);
        std::fflush(stdout);
    }

    size_t contactPoints(const Rung& r) const
    {
        const auto s = sceneAt(base_, r, options_.duration, 1.0);
        return contactPointsOnGrid(s.obstacles, s.string.lengthMetres, r.modes + 1).size();
    }

private:
    // 2 y(2R) - y(R) from the two plain renders (both low-passed alike, so the combination commutes
    // with the filter); their CPU time summed. Empty if either failed.
    Rendered extrapolate(const Rung& r, double amplitudeScale)
    {
        const auto [low, high] = extrapolatedParts(r);
        prefetch({{low, amplitudeScale}, {high, amplitudeScale}}, options_.jobs);
        const Rendered& y1 = done_.at(cacheName(cacheStem_, low, options_.duration, amplitudeScale)).rendered;
        const Rendered& y2 = done_.at(cacheName(cacheStem_, high, options_.duration, amplitudeScale)).rendered;
        Rendered out;
        out.cpuSeconds = y1.cpuSeconds + y2.cpuSeconds;
        out.newtonMax = std::max(y1.newtonMax, y2.newtonMax);
        out.penetration = y2.penetration;
        out.transform = y2.transform;
        if (y1.output.empty() || y2.output.size() != y1.output.size())
            return out;
        out.output.resize(y2.output.size());
        for (size_t i = 0; i < out.output.size(); ++i)
            out.output[i] = 2.0 * y2.output[i] - y1.output[i];
        return out;
    }

    // A render that fails (a non-finite sample) is kept as an empty output: a row, and no pairs.
    static void renderNow(const Scene& scene, Rendered& out)
    {
        const double start = threadCpuSeconds();
        try
        {
            const auto result = renderScene(scene);
            out.output = lowpass(result.output, result.outputRateHz, 20000.0);
            out.newtonMax = result.stats.newtonIterationsMax;
            out.penetration = result.stats.maxPenetrationMetres;
            out.transform = result.stats.transformPath;
        }
        catch (const std::exception& e)
        {
            std::fprintf(stderr, "  failed: %s\n", e.what());
        }
        out.cpuSeconds = threadCpuSeconds() - start;
    }

    void printRender(const Rung& r, double amplitudeScale, const Rendered& out) const
    {
        std::printf("render,%s,%s,%d,%.0f,%d,%zu,%s,%.4g,%d,%.3g,,,,,,\n", stem_.c_str(),
                    amplitudeScale == 1.0 ? "" : "floor", r.modes, r.rateHz, r.intervals, contactPoints(r),
                    out.output.empty()                ? "failed"
                    : r.staticExact && r.extrapolated ? "static-exact-extrapolated"
                    : r.staticExact                   ? "static-exact"
                    : r.extrapolated ? (out.transform ? "transform-extrapolated" : "projection-extrapolated")
                    : out.transform  ? "transform"
                                     : "projection",
                    out.cpuSeconds, out.newtonMax, out.penetration);
        std::fflush(stdout);
    }

    const Options& options_;
    Scene base_;
    std::string stem_;       // the scene's name in the rows
    std::string cacheStem_;  // and in the cache's file names
    std::string cachePath(const std::string& name) const
    {
        return options_.cacheDir.empty() ? "" : options_.cacheDir + "/" + name;
    }

    struct Entry
    {
        Rendered rendered;
        bool printed = false;
    };

    std::map<std::string, Entry> done_;
};

// A ladder's renders and its successive pairs, the finer rung of each pair as the reference.
void runLadder(Study& study, const Ladder& ladder, size_t rungs)
{
    const size_t count = std::min(rungs, ladder.rungs.size());
    for (size_t k = 0; k + 1 < count; ++k)
    {
        const auto& coarse = study.render(ladder.rungs[k]);
        const auto& fine = study.render(ladder.rungs[k + 1]);
        study.printPair("pair", ladder.name, ladder.rungs[k], ladder.rungs[k + 1], coarse, fine);
    }
}

}  // namespace

int main(int argc, char** argv)
{
    Options options;
    if (!parseOptions(argc, argv, options))
        return 2;
    Scene base;
    try
    {
        base = loadSceneFile(options.scenePath);
    }
    catch (const std::exception& e)
    {
        std::fprintf(stderr, "jawari-convergence: cannot load scene '%s': %s\n", options.scenePath.c_str(), e.what());
        return 2;
    }
    if (!options.cacheDir.empty())
        std::filesystem::create_directories(options.cacheDir);
    std::printf("kind,scene,ladder,modes,rate_hz,intervals,contact_points,path,cpu_s,newton_max,penetration_m,"
                "vs_modes,vs_rate_hz,vs_intervals,rel_l2_100ms,lsd_db_2048,lsd_db_1024\n");
    Study study(options, base);
    std::vector<Ladder> ladders;
    for (const auto& ladder : allLadders(options.extend))
        if (std::find(options.knobs.begin(), options.knobs.end(), ladder.name) != options.knobs.end())
            ladders.push_back(ladder);
    if (!options.custom.empty())
        ladders.push_back({"custom", options.custom});
    try
    {
        std::vector<std::pair<Rung, double>> wanted;
        if (options.floor)
            wanted = {{Rung{}, 1.0 + 1e-4}, {Rung{}, 1.0}};
        for (const auto& ladder : ladders)
            for (size_t k = 0; k < std::min(options.rungs, ladder.rungs.size()); ++k)
                wanted.emplace_back(ladder.rungs[k], 1.0);
        study.prefetch(wanted, options.jobs);
        if (options.floor)
        {
            const Rung b;
            study.printPair("floor", "amplitude*(1+1e-4)", b, b, study.render(b, 1.0 + 1e-4), study.render(b));
        }
        for (const auto& ladder : ladders)
            runLadder(study, ladder, options.rungs);
    }
    catch (const std::exception& e)
    {
        std::fprintf(stderr, "jawari-convergence: %s\n", e.what());
        return 1;
    }
    return 0;
}
