// Reference solver speed: real-time factor (simulated seconds per CPU second, one core, one voice)
// on the paper's scenes, side by side in one run. Reports; asserts nothing.
//
//   jawari-bench [seconds]

#include "OfflineRender.h"
#include "Scene.h"

#include <cstdio>
#include <cstdlib>
#include <string>

using namespace jawari;

int main(int argc, char** argv)
{
    const double seconds = argc > 1 ? std::atof(argv[1]) : 1.0;
    std::printf("%-16s %-10s %6s %7s %9s %9s %10s %8s\n", "scene", "path", "modes", "active", "rate Hz", "cpu s",
                "x realtime", "Newton");
    for (const char* name : {"paper-centre", "paper-tanpura"})
    {
        auto scene = loadSceneFile(std::string(JAWARI_RESOURCES_DIR) + "/Scenes/" + name + ".json");
        scene.simulation.durationSeconds = seconds;
        const auto steps = static_cast<long long>(seconds * scene.simulation.rateHz.value_or(kReferenceRateHz));
        RenderStats stats;
        renderInternal(scene, steps, {}, &stats);
        std::printf("%-16s %-10s %6d %7d %9.3g %9.3f %10.2f %8.3f\n", name, stats.transformPath ? "DST-I" : "projection",
                    stats.modes, stats.activeModes, stats.internalRateHz, stats.cpuSeconds, seconds / stats.cpuSeconds,
                    double(stats.newtonIterationsTotal) / double(stats.steps));
    }
    return 0;
}
