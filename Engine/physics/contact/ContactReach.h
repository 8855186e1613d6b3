#pragma once
// Which contact points the string can reach (docs/design.md section 2), so that the step leaves the
// others out: neither projected nor solved (their s is -infinity, infinitely clear).
//
// With the energy-conserving Newton and no external force the energy H never rises, and a string of
// energy H has |u_j + delta_j| <= sqrt(H) reach_j at every point (measure()), so a point whose
// obstacle lies further below than sqrt(H) reach_j cannot touch until H is measured again. H is
// measured every kCheckSteps steps, and at once after anything that can raise it (markStale(): a
// retune, a new height or law, the release, a new state); an external force keeps every point live
// (wakeAll()). A bilateral point (the damped thread) is always live: the string never leaves it.

#include "physics/modes/ExactOscillator.h"
#include "physics/contact/Obstacle.h"
#include "physics/modes/ResidualCompliance.h"
#include "physics/modes/StampedVector.h"

#include <limits>
#include <vector>

namespace jawari
{

class ContactReach
{
public:
    static constexpr int kCheckSteps = 512;

    // OFF: `points` contact points over `modes` modes, every one live. Not `enabled`: they stay live.
    void prepare(int points, int modes, bool enabled);
    bool enabled() const { return enabled_; }

    // RT (no allocation): reach_j for every point from the modes' coefficients of both damping sets,
    // the points' shapes phi_p(x_j) (P x M row-major) and the dropped modes' compliance. Only when enabled.
    void measure(const std::vector<ExactModeCoefficients>& normal, const std::vector<ExactModeCoefficients>& released,
                 const std::vector<double>& shapes, double dt, double mu, const ResidualCompliance& compliance,
                 const std::vector<ContactPoint>& contacts);

    // RT (no allocation), after measure(): tail_j = sqrt((2/mu) sum_p phi_p(x_j)^2 kappa_p^2) over the
    // `count` modes `tailModes` alone, so that those modes' share of u_j is at most sqrt(H) tail_j for a
    // string of energy at most H, and so is their share of the prediction q~ = a q^n - e q^{n-1} (with
    // q^n, a free step from the pair (q^n, q^{n-1}), whose energy is no more: EngagedPoints).
    void measureTail(const int* tailModes, int count, const std::vector<double>& shapes, double mu);
    double tail(int j) const { return tail_[size_t(j)]; }
    // 1.05 sqrt(H) for the H of the last refresh(): sqrt(H) with refresh()'s spare.
    double radius() const { return radius_; }

    // RT: H may have risen: measure it before the next step.
    void markStale() { stale_ = true; }
    // RT, once per step: whether H is to be measured now (stale, or kCheckSteps steps since).
    bool checkDue() { return stale_ || --stepsToCheck_ <= 0; }

    // RT: whether H may have risen since it was last measured (markStale()).
    bool stale() const { return stale_; }

    // RT: the points within sqrt(H) reach_j of their obstacle (5 % spare for the Newton's tolerance),
    // for a string of energy at most H, become the live ones; join(j) is called for each that was not
    // live (the caller gives it its u^n and u^{n-1}), leave(j) for each left out. An obstacle that
    // may rise by up to `rise` (m: a bridge on a body, SharedBody) is that much nearer.
    template <typename Join, typename Leave>
    void refresh(double H, const std::vector<ContactPoint>& contacts, Join&& join, Leave&& leave, double rise = 0.0)
    {
        stale_ = false;
        stepsToCheck_ = kCheckSteps;
        const double radius = reachRadius(H);
        radius_ = radius;
        liveCount_ = 0;
        for (int j = 0; j < static_cast<int>(contacts.size()); ++j)
        {
            const bool reachable = contacts[size_t(j)].law.bilateral  // never left
                                   || !(contacts[size_t(j)].height + rise + radius * reach_[size_t(j)] <= 0.0);  // NaN: reachable
            if (reachable)
            {
                if (!live_[size_t(j)])
                    join(j);
                liveRows_[size_t(liveCount_++)] = j;
            }
            else
                leave(j);
            live_[size_t(j)] = reachable;
        }
    }
    // RT: every point live; join(j) for each that was not.
    template <typename Join>
    void wakeAll(Join&& join)
    {
        const int points = static_cast<int>(live_.size());
        if (liveCount_ == points)
            return;
        for (int j = 0; j < points; ++j)
        {
            if (!live_[size_t(j)])
                join(j);
            live_[size_t(j)] = 1;
            liveRows_[size_t(j)] = j;
        }
        liveCount_ = points;
    }

    int liveCount() const { return liveCount_; }
    const int* liveRows() const { return liveRows_.data(); }  // the live points, ascending
    bool live(int j) const { return live_[size_t(j)] != 0; }

private:
    static double reachRadius(double H);  // 1.05 sqrt(H), H < 0 as 0
    double modesReach(const double* row, const int* modes, int count, double mu) const;

    bool enabled_ = false;
    std::vector<double> reach_;    // per point, m per sqrt(J)
    std::vector<double> tail_;     // per point, m per sqrt(J): measureTail()
    double radius_ = std::numeric_limits<double>::infinity();
    StampedVector<double> kappa_;  // per mode, measure()'s kappa_p
    std::vector<char> live_;       // per point
    std::vector<int> liveRows_;    // the live points, ascending (the first liveCount_ entries)
    int liveCount_ = 0;
    int stepsToCheck_ = 0;
    bool stale_ = true;
};

}  // namespace jawari
