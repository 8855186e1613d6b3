#include "physics/contact/Obstacle.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <numbers>
#include <stdexcept>

namespace jawari
{

Obstacle layThread(Obstacle& bridge, const Thread& thread)
{
    if (!bridge.isDistributed())
        throw std::invalid_argument("a thread lies across a bridge (a parabola or a profile), not a point");
    if (!threadFitsBridge(bridge, thread.offset))
        throw std::invalid_argument("the thread lies off its bridge");
    const double x = std::min(bridge.supportBegin() + thread.offset, bridge.supportEnd());
    if (!(thread.diameter > 0.0))
        throw std::invalid_argument("the thread's diameter must be > 0");
    // The highest support to the rest line: every height moved by one amount. The damped thread
    // holds the string at the rest line, where the bridge's crown grazes it (DAFx-16's h_b = h_c = 0).
    const bool damped = thread.model == ThreadModel::springDamper;
    const double threadTop = damped ? bridge.highestHeight() : bridge.heightAt(x) + thread.diameter;
    const double rest = std::max(threadTop, bridge.highestHeight());
    const double shift = -rest;
    if (bridge.type == ObstacleType::parabola)
        bridge.height += shift;
    for (double& h : bridge.profileHeight)
        h += shift;
    // 0 where the thread carries the string.
    return threadObstacle(thread, x, threadTop - rest, bridge.spacing);
}

Obstacle threadObstacle(const Thread& thread, double position, double height, double spacing)
{
    Obstacle point;
    point.position = position;
    point.height = height;
    if (thread.model == ThreadModel::contact)
    {
        point.type = ObstacleType::point;
        point.width = thread.diameter;
        point.law = thread.law;
        return point;
    }
    if (!(thread.width > 0.0) || !(thread.stiffness > 0.0) || !(thread.damping >= 0.0))
        throw std::invalid_argument("the thread's width and stiffness must be > 0 and its damping >= 0");
    point.type = ObstacleType::band;
    point.width = thread.width;
    point.spacing = spacing;
    point.law.bilateral = true;
    point.law.exponent = 1.0;
    point.law.stiffness = thread.stiffness / thread.width;
    point.law.damping = thread.damping / thread.width;
    return point;
}

bool threadFitsBridge(const Obstacle& bridge, double offset)
{
    constexpr double tolerance = 1e-9;  // m
    return offset >= 0.0 && bridge.supportBegin() + offset <= bridge.supportEnd() + tolerance;
}

double Obstacle::supportBegin() const
{
    switch (type)
    {
        case ObstacleType::point: return position;
        case ObstacleType::profile: return profileX.empty() ? 0.0 : profileX.front();
        case ObstacleType::parabola:
        case ObstacleType::band: return position - 0.5 * width;
    }
    return position;
}

double Obstacle::supportEnd() const
{
    switch (type)
    {
        case ObstacleType::point: return position;
        case ObstacleType::profile: return profileX.empty() ? 0.0 : profileX.back();
        case ObstacleType::parabola:
        case ObstacleType::band: return position + 0.5 * width;
    }
    return position;
}

double Obstacle::highestHeight() const
{
    switch (type)
    {
        case ObstacleType::point:
        case ObstacleType::band: return height;
        case ObstacleType::parabola:  // the apex is the support's centre
            return curvature >= 0.0 ? height : std::max(heightAt(supportBegin()), heightAt(supportEnd()));
        case ObstacleType::profile:
            return profileHeight.empty() ? height : *std::max_element(profileHeight.begin(), profileHeight.end());
    }
    return height;
}

double Obstacle::heightAt(double x) const
{
    switch (type)
    {
        case ObstacleType::point:
        case ObstacleType::band: return height;
        case ObstacleType::parabola:
        {
            const double d = x - position;
            return height - 0.5 * curvature * d * d;
        }
        case ObstacleType::profile:
        {
            if (profileX.size() == 1)
                return profileHeight.front();
            const auto it = std::upper_bound(profileX.begin(), profileX.end(), x);
            const auto hi = std::clamp<std::ptrdiff_t>(std::distance(profileX.begin(), it), 1,
                                                       static_cast<std::ptrdiff_t>(profileX.size()) - 1);
            const auto lo = hi - 1;
            const double t = (x - profileX[lo]) / (profileX[hi] - profileX[lo]);
            return profileHeight[lo] + t * (profileHeight[hi] - profileHeight[lo]);
        }
    }
    return height;
}

namespace
{
// A band's points: the nodes i spacing strictly inside it, weighted by the raised cosine, or one
// point at its centre. solverNode(x) gives the solver's node at x or -1; dx is the solver's spacing.
template <typename SolverNode>
void addBandPoints(const Obstacle& band, double spacing, int intervals, double dx, SolverNode&& solverNode,
                   std::vector<ContactPoint>& points)
{
    const int first = std::max(1, static_cast<int>(std::floor(band.supportBegin() / spacing + 1e-9)) + 1);
    const int last = std::min(intervals - 1, static_cast<int>(std::ceil(band.supportEnd() / spacing - 1e-9)) - 1);
    const size_t start = points.size();
    double sum = 0.0;
    for (int i = first; i <= last; ++i)
    {
        const int node = solverNode(i * spacing);
        const double at = node >= 0 ? node * dx : i * spacing;
        const double psi = std::cos(std::numbers::pi * (at - band.position) / band.width);
        if (!(psi > 0.0))
            continue;
        points.push_back({at, psi, band.height, band.law, node});
        sum += psi;
    }
    if (points.size() == start)
    {
        points.push_back({band.position, band.width, band.height, band.law, solverNode(band.position)});
        return;
    }
    for (size_t k = start; k < points.size(); ++k)
        points[k].weight *= band.width / sum;
}
}  // namespace

int contactGridIntervals(const Obstacle& obstacle, double lengthMetres)
{
    if (!(obstacle.spacing > 0.0))
        return kContactGridIntervals;
    return static_cast<int>(std::clamp(std::round(lengthMetres / obstacle.spacing), 2.0, 1e7));
}

std::vector<ContactPoint> contactPointsOnGrid(const std::vector<Obstacle>& obstacles, double lengthMetres,
                                              int gridIntervals)
{
    const double dx = lengthMetres / gridIntervals;
    // The node of the solver's grid at x, or -1.
    auto solverNode = [&](double x) {
        const double node = std::round(x / dx);
        return std::abs(x / dx - node) < 1e-9 && node > 0 && node < gridIntervals ? static_cast<int>(node) : -1;
    };
    std::vector<ContactPoint> points;
    for (const auto& ob : obstacles)
    {
        if (!ob.isDistributed())
        {
            points.push_back({ob.position, ob.width, ob.height, ob.law, solverNode(ob.position)});
            continue;
        }
        const int intervals = contactGridIntervals(ob, lengthMetres);
        const double spacing = lengthMetres / intervals;
        if (ob.type == ObstacleType::band)
        {
            addBandPoints(ob, spacing, intervals, dx, solverNode, points);
            continue;
        }
        const int first = std::max(1, static_cast<int>(std::ceil(ob.supportBegin() / spacing - 1e-9)));
        const int last = std::min(intervals - 1, static_cast<int>(std::floor(ob.supportEnd() / spacing + 1e-9)));
        for (int i = first; i <= last; ++i)
        {
            // On the solver's grid when the two grids share the node: x from the solver's index then,
            // so the transform path sees exactly its node.
            const double x = i * spacing;
            const int node = solverNode(x);
            const double at = node >= 0 ? node * dx : x;
            points.push_back({at, spacing, ob.heightAt(at), ob.law, node});
        }
    }
    return points;
}

}  // namespace jawari
