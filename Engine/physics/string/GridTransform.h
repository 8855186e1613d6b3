#pragma once
// The reference grid's fast way to the contact points (docs/design.md section 2). With M = N - 1
// modes and every contact point on its own node x_i = i L/N, the values at the nodes are a sine
// transform of the modal state (a DST-I), O(M log M) instead of O(M P), and Phi Phi^T W is
// diagonal. The solver sees only this interface; the transform itself (FFTW) is
// offline/DstTransform, so the physics carries no FFT library.

#include "physics/contact/Obstacle.h"

#include <cstddef>
#include <functional>
#include <memory>
#include <stdexcept>
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

// A solver's transform, owned. Solvers are copied only without one (the voices' backups for a
// second core: StringWorker); the reference's solvers, on the transform, are never copied, and
// copying one is refused.
class OwnedGridTransform
{
public:
    OwnedGridTransform() = default;
    OwnedGridTransform(std::unique_ptr<GridTransform> transform) : transform_(std::move(transform)) {}
    OwnedGridTransform(const OwnedGridTransform&) = delete;
    OwnedGridTransform& operator=(const OwnedGridTransform& other)
    {
        refuseCopyOf(other);
        refuseCopyOf(*this);
        return *this;
    }
    OwnedGridTransform(OwnedGridTransform&&) = default;
    OwnedGridTransform& operator=(OwnedGridTransform&&) = default;

    GridTransform* operator->() const { return transform_.get(); }
    explicit operator bool() const { return transform_ != nullptr; }
    bool operator==(std::nullptr_t) const { return transform_ == nullptr; }

private:
    static void refuseCopyOf(const OwnedGridTransform& t)
    {
        if (t.transform_)
            throw std::logic_error("a solver on the grid transform is not copied");
    }
    std::unique_ptr<GridTransform> transform_;
};

}  // namespace jawari
