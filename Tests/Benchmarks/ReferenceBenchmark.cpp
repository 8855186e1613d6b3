// Reference solver speed: real-time factor (simulated seconds per CPU second, one core, one voice)
// on the paper's scenes, side by side in one run. Reports; asserts nothing.
//
//   jawari-bench [seconds]

#include "offline/CpuClock.h"
#include "offline/OfflineRender.h"
#include "offline/Scene.h"
#include "physics/modes/ModalKernels.h"
#include "realtime/voice/Denormals.h"
#include "realtime/voice/Quality.h"
#include "realtime/voice/Voice.h"

#include <cmath>
#include <vector>

#include <cstdio>
#include <cstdlib>
#include <string>

using namespace jawari;

namespace
{
// The same two-step kernel, compiled without vectorisation, to show what the vector units give.
__attribute__((optimize("no-tree-vectorize"))) void pairStepScalar(const double* a, const double* e, double* X,
                                                                   double* Y, double* settled, const double* h,
                                                                   const double* phi, double c1, double c2, int M,
                                                                   double& y1, double& u1, double& y2, double& u2)
{
    y1 = u1 = y2 = u2 = 0.0;
    for (int p = 0; p < M; ++p)
    {
        const double before = X[p] + c1 * phi[p];
        const double now = Y[p] + (c1 * a[p] + c2) * phi[p];
        const double t1 = a[p] * now - e[p] * before;
        const double t2 = a[p] * t1 - e[p] * now;
        settled[p] = now;
        X[p] = t1;
        Y[p] = t2;
        y1 += h[p] * t1;
        u1 += phi[p] * t1;
        y2 += h[p] * t2;
        u2 += phi[p] * t2;
    }
}

// ns per fused multiply-add at this core's peak: independent chains of vector FMAs, as many as
// keep both pipes busy, at 256 and 512 bits (the faster counts).
typedef double Vec4 __attribute__((vector_size(32)));
typedef double Vec8 __attribute__((vector_size(64)));
template <typename Vec>
double nsPerFmaLane()
{
    constexpr int lanes = sizeof(Vec) / 8, chains = 16;
    Vec acc[chains], m, c;
    for (int k = 0; k < lanes; ++k)
    {
        m[k] = 0.999999;
        c[k] = 1e-7 * (k + 1);
    }
    for (int j = 0; j < chains; ++j)
        acc[j] = m * (1.0 + j);
    const long long rounds = 20000000;
    const double t0 = threadCpuSeconds();
    for (long long n = 0; n < rounds; ++n)
    {
        for (int j = 0; j < chains; ++j)
            acc[j] = acc[j] * m + c;  // contracted to one FMA (as in the kernels)
    }
    const double spent = threadCpuSeconds() - t0;
    double sink = 0.0;
    for (int j = 0; j < chains; ++j)
        for (int k = 0; k < lanes; ++k)
            sink += acc[j][k];
    if (!(sink == sink))
        std::printf("(nan)\n");
    return spent / (double(rounds) * chains * lanes) * 1e9;
}

// ns per mode and step of the per-mode loop, vectorised and scalar, in the same run, and against
// the core's peak FMA rate: the pass does 11 multiply-adds (or multiplies) per mode for two steps.
void kernelCheck()
{
    ScopedFlushDenormals noDenormals;
    const int M = 480;  // not a multiple of 512: arrays 4 KiB apart would alias (see ModalSolver)
    std::vector<double> a(M), e(M), X(M, 1e-4), Y(M, 1e-4), S(M), h(M), phi(M);
    for (int p = 0; p < M; ++p)
    {
        a[p] = 2.0 * std::cos(1e-3 * (p + 1)) * 0.9999;
        e[p] = 0.9998;
        h[p] = std::sin(0.3 * p);
        phi[p] = std::cos(0.2 * p);
    }
    const int passes = 200000;
    double sink = 0.0;
    kernels::PairReadout readout;
    double t0 = threadCpuSeconds();
    for (int n = 0; n < passes; ++n)
    {
        kernels::pairStep(a.data(), e.data(), X.data(), Y.data(), S.data(), h.data(), nullptr, phi.data(), 1e-12, 0.0,
                          M, M, false, readout);
        sink += readout.pickup1 + readout.contact2;
    }
    const double vectorised = (threadCpuSeconds() - t0) / (2.0 * passes * M) * 1e9;
    t0 = threadCpuSeconds();
    for (int n = 0; n < passes; ++n)
    {
        pairStepScalar(a.data(), e.data(), X.data(), Y.data(), S.data(), h.data(), phi.data(), 1e-12, 0.0, M,
                       readout.pickup1, readout.contact1, readout.pickup2, readout.contact2);
        sink += readout.pickup1 + readout.contact2;
    }
    const double scalar = (threadCpuSeconds() - t0) / (2.0 * passes * M) * 1e9;
    std::printf("per-mode loop (two steps a pass, 480 modes): %.3f ns per mode-step vectorised, %.3f scalar: %.2fx "
                "(checksum %.3g)\n",
                vectorised, scalar, scalar / vectorised, sink);
    const double peak = std::min(nsPerFmaLane<Vec4>(), nsPerFmaLane<Vec8>());
    std::printf("this core's peak: %.4f ns per double FMA; the loop's 5.5 FMAs per mode-step would take %.3f ns at it: "
                "the loop runs at %.0f %% of the peak\n\n",
                peak, 5.5 * peak, 100.0 * 5.5 * peak / vectorised);
}
// The voice at standard quality in 256-sample blocks at 48 kHz, plucked every half second: the
// worst block's CPU time against its real-time budget, and the most Newton iterations in a step.
struct BlockLoad
{
    double mean = 0.0, worst = 0.0;  // % of the block's real-time budget
    int iterations = 0;
};
BlockLoad playBlocks(const VoiceConfig& config)
{
    Voice voice(config);
    ScopedFlushDenormals noDenormals;
    const int block = 256;
    const double budget = block / 48000.0;
    std::vector<double> out(block);
    double worst = 0.0, total = 0.0;
    int iterations = 0;
    const int blocks = 48000 * 10 / block;  // 10 s
    for (int b = 0; b < blocks; ++b)
    {
        if (b % (24000 / block) == 0)
            voice.pluckWithPulse(1.0);
        const double start = threadCpuSeconds();
        voice.process(out.data(), block);
        const double spent = threadCpuSeconds() - start;
        worst = std::max(worst, spent);
        total += spent;
        iterations = std::max(iterations, voice.takeMaxIterations());
    }
    return {100.0 * total / blocks / budget, 100.0 * worst / budget, iterations};
}
// The same voice without its obstacle as well: what the modes, pickup and decimator cost alone,
// the ceiling of the real-time factor for these M and R whatever the contact solve costs.
void worstBlock(const char* name, const Scene& scene)
{
    const auto q = resolveQuality(*qualityByName("standard"), scene.string, 48000.0);
    VoiceConfig config;
    config.string = scene.string;
    config.obstacles = scene.obstacles;
    config.modes = q.modes;
    config.oversampling = q.oversampling;
    const BlockLoad load = playBlocks(config);
    config.obstacles.clear();
    const BlockLoad free = playBlocks(config);
    std::printf("%-14s standard voice (%d modes, %.0f kHz), 256-sample blocks for 10 s: mean %.1f %%, worst %.1f %% of "
                "the block's real-time budget (5.33 ms), %.1fx real time; most Newton iterations in a step %d. "
                "Without its obstacle: mean %.1f %%, %.1fx\n",
                name, q.modes, q.oversampling * 48.0, load.mean, load.worst, 100.0 / load.mean, load.iterations,
                free.mean, 100.0 / free.mean);
}
}  // namespace

int main(int argc, char** argv)
{
    const double seconds = argc > 1 ? std::atof(argv[1]) : 1.0;
    kernelCheck();
    std::printf("%-16s %-10s %6s %7s %9s %9s %10s %8s\n", "scene", "path", "modes", "active", "rate Hz", "cpu s",
                "x realtime", "Newton");
    for (const char* name : {"paper-centre", "paper-tanpura"})
    {
        auto scene = loadSceneFile(std::string(JAWARI_RESOURCES_DIR) + "/Scenes/" + name + ".json");
        scene.simulation.durationSeconds = seconds;
        const auto steps = static_cast<long long>(seconds * scene.simulation.rateHz.value_or(kReferenceRateHz));
        RenderStats stats;
        renderInternal(scene, steps, {}, &stats);
        std::printf("%-16s %-10s %6d %7d %9.3g %9.3f %10.2f %8.3f\n", name,
                    stats.transformPath ? "DST-I" : "projection", stats.modes, stats.activeModes, stats.internalRateHz,
                    stats.cpuSeconds, seconds / stats.cpuSeconds,
                    double(stats.newtonIterationsTotal) / double(stats.steps));
    }
    std::printf("\n");
    for (const char* name : {"paper-centre", "paper-tanpura"})
        worstBlock(name, loadSceneFile(std::string(JAWARI_RESOURCES_DIR) + "/Scenes/" + name + ".json"));
    return 0;
}
