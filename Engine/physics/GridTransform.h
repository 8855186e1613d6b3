#pragma once
// The reference grid's fast way to the contact points (docs/design.md section 2). With M = N - 1
// modes and every contact point on its own node x_i = i L/N, the values at the nodes are a sine
// transform of the modal state (a DST-I), O(M log M) instead of O(M P), and Phi Phi^T W is
// diagonal. The solver sees only this interface; the transform itself (FFTW) is
// offline/DstTransform, so the physics carries no FFT library.

#include "physics/Obstacle.h"

#include <functional>
#include <memory>
#include <vector>

namespace jawari
{

class GridTransform
{
public:
    virtual ~GridTransform() = default;
    // u_j = sum_p q_p phi_p(x_j) at the contact points' nodes, from M values of q.
    virtual void sample(const double* q, double* u) = 0;
    // The same through buffers of its own, so a reading between steps leaves sample()'s alone.
    virtual void sampleAside(const double* q, double* u) const = 0;
    // q_p += factor sum_j F_j phi_p(x_j), F one value per contact point.
    virtual void spread(const double* F, double factor, double* q) = 0;
};

// Builds the transform for a solver's contact points, M modes and string length. OFF.
using GridTransformFactory = std::function<std::unique_ptr<GridTransform>(const std::vector<ContactPoint>& contacts,
                                                                          double lengthMetres, int modes)>;

}  // namespace jawari
