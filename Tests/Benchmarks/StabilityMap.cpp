// Where each contact method fails (docs/design.md section 4): K from 1e6 to 1e16, internal rate from
// 1x to 64x of 48 kHz, alpha in {1, 1.3, 2, 3}; the paper-centre string and obstacle with 100
// modes, 0.1 s. The solver runs bare (no muting guard), and a run fails by
//   nan          a non-finite state,
//   energy       H above 1.000001 H(0) (nothing feeds this string energy),
//   penetration  more than 1 mm into the obstacle.
// Writes CSV: method, alpha, stiffness, rate_hz, outcome, max_penetration_m, max_energy_ratio.
//
//   jawari-stability [out.csv]

#include "offline/Scene.h"
#include "physics/modes/ModalSolver.h"
#include "realtime/voice/Voice.h"

#include <cmath>
#include <cstdio>
#include <string>

using namespace jawari;

int main(int argc, char** argv)
{
    if (argc > 2 || (argc == 2 && argv[1][0] == '-'))
    {
        std::fprintf(stderr, "usage: jawari-stability [out.csv]\n");
        return 2;
    }
    FILE* out = argc > 1 ? std::fopen(argv[1], "w") : stdout;
    if (out == nullptr)
        return 1;
    const auto scene = loadSceneFile(std::string(JAWARI_RESOURCES_DIR) + "/Scenes/paper-centre.json");
    std::fprintf(out, "method,alpha,stiffness,rate_hz,outcome,max_penetration_m,max_energy_ratio\n");
    const struct
    {
        ContactMethod method;
        const char* name;
    } methods[] = {{ContactMethod::energyConserving, "energy-conserving"},
                   {ContactMethod::quadratised, "quadratised"},
                   {ContactMethod::penalty, "penalty"},
                   {ContactMethod::quadraticSpline, "quadratic-spline"}};
    for (const auto& m : methods)
        for (double alpha : {1.0, 1.3, 2.0, 3.0})
            for (int e = 6; e <= 16; ++e)
                for (int factor : {1, 2, 4, 8, 16, 32, 64})
                {
                    VoiceConfig v;
                    v.string = scene.string;
                    v.obstacles = scene.obstacles;
                    v.obstacles[0].law = {std::pow(10.0, e), alpha};
                    v.modes = 100;
                    v.oversampling = factor;
                    v.method = m.method;
                    ModalSolver solver(voiceSolverConfig(v));
                    solver.setInitialDisplacement(pluckModalShape(scene.string.lengthMetres, 100, 0.501, 1.5e-3));
                    const double H0 = solver.energy().total;
                    const long steps = std::lround(0.1 * factor * 48000.0);
                    double penetration = 0.0, ratio = 1.0;
                    const char* outcome = "ok";
                    for (long n = 0; n < steps; ++n)
                    {
                        solver.step();
                        penetration = std::max(penetration, solver.lastMaxPenetration());
                        if (!std::isfinite(solver.pickup()) || !std::isfinite(solver.lastMaxPenetration()))
                        {
                            outcome = "nan";
                            break;
                        }
                        if (n % 64 == 63 || n == steps - 1)
                        {
                            const double H = solver.energy().total;
                            if (!std::isfinite(H))
                            {
                                outcome = "nan";
                                break;
                            }
                            ratio = std::max(ratio, H / H0);
                            if (ratio > 1.000001)
                            {
                                outcome = "energy";
                                break;
                            }
                        }
                        if (penetration > 1e-3)
                        {
                            outcome = "penetration";
                            break;
                        }
                    }
                    std::fprintf(out, "%s,%g,%g,%g,%s,%.4g,%.6g\n", m.name, alpha, std::pow(10.0, e), factor * 48000.0,
                                 outcome, penetration, ratio);
                    std::fflush(out);
                }
    if (out != stdout)
        std::fclose(out);
    return 0;
}
