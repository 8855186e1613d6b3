#pragma once
// Strings in their own solvers on the tanpura body, for the shared body's tests (SharedBody.h):
// the scenes' strings at kBodyTestModes modes and kBodyTestRate, each plucked or at rest.

#include "TestSupport.h"
#include "offline/Scene.h"
#include "physics/body/FactoryBodies.h"
#include "physics/modes/ModalSolver.h"
#include "physics/string/StringDiscretisation.h"

#include <deque>
#include <string>
#include <vector>

namespace jawari::test
{

inline constexpr int kBodyTestModes = 150;
inline constexpr double kBodyTestRate = 192000.0;

struct Strings
{
    std::deque<ModalSolver> solvers;  // built in place: a solver is not copied
    std::vector<ModalSolver*> pointers;
};

// The scenes' strings at kBodyTestModes modes and kBodyTestRate, lossless when asked; the ones
// `plucked` from the scene's pluck, the others at rest; each string left to choose its points or
// with every one live.
inline Strings stringsOf(const std::vector<Scene>& scenes, const std::vector<bool>& plucked, bool reach, bool lossless)
{
    Strings s;
    for (size_t i = 0; i < scenes.size(); ++i)
    {
        auto string = scenes[i].string;
        if (lossless)
            string.damping.law = DampingLaw::none;
        auto config = stringSolverConfig(string, scenes[i].obstacles, kBodyTestModes, kBodyTestRate,
                                         scenes[i].pickup.position, PickupQuantity::displacement);
        config.leaveOutOfReach = reach;
        auto& solver = s.solvers.emplace_back(config);
        if (plucked[i])
            solver.setInitialDisplacement(pluckModalShape(
                string.lengthMetres, kBodyTestModes, scenes[i].excitation.position, scenes[i].excitation.amplitude));
    }
    for (auto& solver : s.solvers)
        s.pointers.push_back(&solver);
    return s;
}

inline ModalBody tanpuraBody(bool lossless)
{
    ModalBody body = *factoryBody("tanpura");
    if (lossless)
        for (auto& mode : body.modes)
            mode.sigma = 0.0;
    return body;
}

}  // namespace jawari::test
