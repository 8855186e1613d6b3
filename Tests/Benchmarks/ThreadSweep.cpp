// jawari-thread-sweep: how the tanpura's sound moves with its thread, with one polarisation and
// with two (docs/measurements.md, "The thread's position, explored"). Measures and reports.
//
//   jawari-thread-sweep [--reference] [--coupling-at-thread]
//       the voice at its automatic quality, or a reference of 600 modes per polarisation at 1 MHz;
//       the second polarisation's spring 1 cm from the far end (as the instrument couples it), or
//       at the thread
//
// The paper's tanpura string over a parabolic bridge on [0, 10 mm] (apex at 5 mm, curvature
// 20 /m). A thread of diameter 0.2 mm lies across it at x_t (layThread: the string rests on the
// thread, so the bridge lies 0.2 mm below the string there, and the bridge's apex is closer to the
// string the further the thread is from it). For each x_t: the spectral centroid above the 10th partial over the
// first second, and at 0.05 s and 0.9 s, and the energy above the 10th partial against the energy
// from 150 Hz to 20 kHz over the first second (dB).

#include "offline/Analysis.h"
#include "offline/OfflineRender.h"
#include "offline/Scene.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <numbers>
#include <string>
#include <vector>

using namespace jawari;

namespace
{
constexpr double kCurvature = 20.0, kThread = 0.2e-3, kApex = 0.005;

// Energy above `lowHz` against the energy from 150 Hz, both to 20 kHz, over the first second (dB).
double energyAboveDb(const std::vector<double>& y, double lowHz)
{
    const size_t fftSize = 65536;
    const auto power = powerSpectrum(y.data(), std::min<size_t>(y.size(), 48000), fftSize);
    double above = 0.0, all = 0.0;
    for (size_t k = 1; k < power.size(); ++k)
    {
        const double f = double(k) * 48000.0 / double(fftSize);
        if (f > 20000.0)
            break;
        all += f > 150.0 ? power[k] : 0.0;
        above += f > lowHz ? power[k] : 0.0;
    }
    return 10.0 * std::log10(above / all);
}

Scene sweepScene(double threadAt, int polarisations, bool reference, bool couplingAtThread)
{
    Scene s = loadSceneFile(std::string(JAWARI_RESOURCES_DIR) + "/Scenes/paper-tanpura.json");
    Obstacle bridge;
    bridge.type = ObstacleType::parabola;
    bridge.position = kApex;
    bridge.width = 2.0 * kApex;
    bridge.curvature = kCurvature;
    bridge.law = {1e13, 1.3};
    const Obstacle thread = layThread(bridge, Thread{threadAt, kThread, {1e13, 1.3}});
    s.obstacles = {bridge, thread};
    if (reference)
    {
        s.simulation.modes = 600;
        s.simulation.rateHz = 1e6;
    }
    else
    {
        s.simulation.reference = false;
        s.simulation.contact = ContactMethod::energyConserving;
        s.simulation.forgetConfiguration();
    }
    if (polarisations == 2)
    {
        // Coupled as the instrument couples them (InstrumentStructure::polarisations), the pluck
        // 0.3 rad out of the vertical.
        SecondPolarisation second;
        second.detuning = 1e-3;
        second.excitationAngle = 0.3;
        second.coupling = {couplingAtThread ? threadAt : s.string.lengthMetres - 0.01, std::numbers::pi / 6,
                           0.1 * s.string.tensionNewtons / 0.01};
        s.secondPolarisation = second;
        s.excitation.angle = 0.3;
    }
    return s;
}
}  // namespace

int main(int argc, char* argv[])
{
    bool reference = false, couplingAtThread = false;
    for (int i = 1; i < argc; ++i)
    {
        if (std::strcmp(argv[i], "--reference") == 0)
            reference = true;
        else if (std::strcmp(argv[i], "--coupling-at-thread") == 0)
            couplingAtThread = true;
        else
        {
            std::fprintf(stderr, "jawari-thread-sweep: unknown option %s (--reference, --coupling-at-thread)\n", argv[i]);
            return 2;
        }
    }
    const double f0 = 195.998, band = 10.5 * f0;
    for (const int polarisations : {1, 2})
    {
        std::printf("%d polarisation%s, %s\n", polarisations, polarisations == 1 ? "" : "s",
                    reference ? "reference (600 modes each at 1 MHz)" : "the voice at its automatic quality");
        double lowest = 1e9, highest = 0.0, leastEnergy = 1e9, mostEnergy = -1e9;
        for (const double x : {0.001, 0.002, 0.003, 0.004, 0.005, 0.006, 0.008})
        {
            const auto y = renderScene(sweepScene(x, polarisations, reference, couplingAtThread)).output;
            const double whole = spectralCentroid(y, 48000, 0, 48000, band, 20000);
            const double energy = energyAboveDb(y, band);
            lowest = std::min(lowest, whole);
            highest = std::max(highest, whole);
            leastEnergy = std::min(leastEnergy, energy);
            mostEnergy = std::max(mostEnergy, energy);
            std::printf("  thread at %.0f mm: centroid above the 10th partial %.0f Hz over the first second (%.0f Hz at "
                        "0.05 s, %.0f Hz at 0.9 s); energy above it %.2f dB\n",
                        x * 1e3, whole, spectralCentroid(y, 48000, 2400, 4800, band, 20000),
                        spectralCentroid(y, 48000, 43200, 4800, band, 20000), energy);
        }
        std::printf("  range over the sweep: %.0f Hz (%.0f to %.0f); energy above the 10th partial %.2f dB (%.2f to "
                    "%.2f dB)\n",
                    highest - lowest, lowest, highest, mostEnergy - leastEnergy, leastEnergy, mostEnergy);
    }
    return 0;
}
