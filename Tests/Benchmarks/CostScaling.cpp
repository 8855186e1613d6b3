// How the voice's cost scales (docs/design.md section 5: cost ~ R x (M + M P)): real-time factor of the
// default voice (energy-conserving Newton, residual compliance) at 384 kHz for 1 s of the paper
// string, against M with one point obstacle, and against the number of contact points P (a flat
// profile 10 um below the string covering P nodes of the M = 200 grid) at M = 200.
// Writes CSV: series, modes, contact_points, rate_hz, realtime_factor.
//
//   jawari-scaling [out.csv]

#include "offline/CpuClock.h"
#include "offline/Scene.h"
#include "realtime/voice/Denormals.h"
#include "realtime/voice/Voice.h"

#include <cstdio>
#include <string>
#include <vector>

using namespace jawari;

namespace
{
double realtimeFactor(const VoiceConfig& config, int& points)
{
    Voice voice(config);
    points = voice.contactPoints();
    voice.setInitialShape(0.501, 1.5e-3);
    std::vector<double> block(480);
    ScopedFlushDenormals noDenormals;
    const double start = threadCpuSeconds();
    for (int b = 0; b < 100; ++b)
        voice.process(block.data(), 480);
    return 1.0 / (threadCpuSeconds() - start);
}
}  // namespace

int main(int argc, char** argv)
{
    if (argc > 2 || (argc == 2 && argv[1][0] == '-'))
    {
        std::fprintf(stderr, "usage: jawari-scaling [out.csv]\n");
        return 2;
    }
    FILE* out = argc > 1 ? std::fopen(argv[1], "w") : stdout;
    if (out == nullptr)
        return 1;
    const auto scene = loadSceneFile(std::string(JAWARI_RESOURCES_DIR) + "/Scenes/paper-tanpura.json");
    std::fprintf(out, "series,modes,contact_points,rate_hz,realtime_factor\n");
    VoiceConfig base;
    base.string = scene.string;
    base.obstacles = scene.obstacles;
    base.oversampling = 8;
    for (int M : {50, 100, 200, 400, 800, 1600})
    {
        auto v = base;
        v.modes = M;
        int points = 0;
        const double rtf = realtimeFactor(v, points);
        std::fprintf(out, "modes,%d,%d,%g,%.4g\n", M, points, 384000.0, rtf);
    }
    const double dx = scene.string.lengthMetres / 201.0;
    for (int P : {1, 2, 4, 8, 16, 32, 64})
    {
        auto v = base;
        v.modes = 200;
        Obstacle flat;
        flat.type = ObstacleType::profile;
        flat.profileX = {0.5 * dx, (P + 0.5) * dx};
        flat.profileHeight = {-1e-5, -1e-5};
        v.obstacles = {flat};
        int points = 0;
        const double rtf = realtimeFactor(v, points);
        std::fprintf(out, "points,%d,%d,%g,%.4g\n", 200, points, 384000.0, rtf);
    }
    if (out != stdout)
        std::fclose(out);
    return 0;
}
