// The delayed link between the strings and the body (SharedBody::setDelayedLink; docs/design.md,
// "A delayed link, for comparison"): each string meets the body through a lossless line of its own.
#include "physics/body/SharedBody.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace jawari
{

void SharedBody::setDelayedLink(double impedance)
{
    if (!(std::isfinite(impedance) && impedance >= 0.0))
        throw std::invalid_argument("a delayed link's impedance is a finite number of kg/s >= 0 (0: none)");
    linkImpedance_ = impedance;
    links_.fill({bridge_, bridgeBefore_, 0.0, 0.0});  // each node where the bridge is, the lines at rest
    resolved_ = false;
    reach_.chooseAgain();
}

// The waves in transit, each sent at the last step and arriving at the next: a wave a carries
// dt a^2 / (4 R) (J).
double SharedBody::lineEnergy(int count) const
{
    if (linkImpedance_ == 0.0)
        return 0.0;
    double sum = 0.0;
    for (int i = 0; i < std::min(count, kMostLinked); ++i)
        sum += links_[size_t(i)].toString * links_[size_t(i)].toString
               + links_[size_t(i)].toBody * links_[size_t(i)].toBody;
    return dt_ / (4.0 * linkImpedance_) * sum;
}

// The delayed link (setDelayedLink). Each line, of impedance R and one step's delay, carries from each
// end C + R q, C its compression and q the velocity into the line there, to arrive at the other end
// a step later, where it is C - R q (the lossless line's Riemann invariants, sampled at its delay). At the
// string's end q = -v, v its node's centred velocity (w^{n+1} - w^{n-1}) / (2 dt); the node is
// massless, so C = -F_s, F_s the string's force on it (< 0 pressing down). At the body's end q = V,
// the bridge's centred velocity, and the body is pushed by -sum C. Given the waves arriving, the
// body's bridge is linear in its force, and each string with its node is a string on a moving
// bridge of compliance 2 dt / R: neither waits for the other. The power into a line at an end, C q,
// is (C + R q)^2 / (4 R) sent less (C - R q)^2 / (4 R) received, so the line holds the waves in
// transit (lineEnergy) and strings + lines + body keep the joined balance.
void SharedBody::stepLinked(ModalSolver* const* strings, int count, double predicted)
{
    if (count > kMostLinked)
        throw std::invalid_argument("a delayed link joins at most " + std::to_string(kMostLinked) + " strings");
    for (int i = 0; i < count; ++i)
    {
        strings[i]->wakeAllPoints();  // the reach's budgets assume the rigid bridge
        strings[i]->predictOnMovingBridge();
    }
    // The body: F = -sum (a_i + R V) with V = (w~ + beta F - w^{n-1}) / (2 dt), a_i the waves arriving.
    const double R = linkImpedance_, N = count;
    double arriving = 0.0;
    for (int i = 0; i < count; ++i)
        arriving += links_[size_t(i)].toBody;
    force_ = (-arriving - N * R * (predicted - bridgeBefore_) / (2.0 * dt_)) / (1.0 + N * R * beta_ / (2.0 * dt_));
    const double V = (predicted + beta_ * force_ - bridgeBefore_) / (2.0 * dt_);
    evaluations_ = trials_ = 0;
    for (int i = 0; i < count; ++i)
    {
        LinkEnd& end = links_[size_t(i)];
        double node = 0.0;
        const double compression = -solveNode(*strings[i], end.nodeBefore, end.toString, node);
        const double v = (node - end.nodeBefore) / (2.0 * dt_);
        const double atBody = end.toBody + R * V;  // the line's compression at the body's end
        end.toString = atBody + R * V;
        end.toBody = compression - R * v;
        end.nodeBefore = end.node;
        end.node = node;
    }
    for (int i = 0; i < count; ++i)
        strings[i]->finishOnMovingBridge();
}

}  // namespace jawari
