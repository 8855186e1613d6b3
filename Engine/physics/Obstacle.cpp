#include "physics/Obstacle.h"

#include <algorithm>
#include <cmath>
#include <iterator>

namespace jawari
{

double Obstacle::supportBegin() const
{
    switch (type)
    {
        case ObstacleType::point: return position;
        case ObstacleType::profile: return profileX.empty() ? 0.0 : profileX.front();
        case ObstacleType::parabola: return position - 0.5 * width;
    }
    return position;
}

double Obstacle::supportEnd() const
{
    switch (type)
    {
        case ObstacleType::point: return position;
        case ObstacleType::profile: return profileX.empty() ? 0.0 : profileX.back();
        case ObstacleType::parabola: return position + 0.5 * width;
    }
    return position;
}

double Obstacle::heightAt(double x) const
{
    switch (type)
    {
        case ObstacleType::point: return height;
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

std::vector<ContactPoint> contactPointsOnGrid(const std::vector<Obstacle>& obstacles, double lengthMetres,
                                              int gridIntervals)
{
    const double dx = lengthMetres / gridIntervals;
    std::vector<ContactPoint> points;
    for (const auto& ob : obstacles)
    {
        if (!ob.isDistributed())
        {
            ContactPoint c{ob.position, ob.width, ob.height, ob.law, -1};
            const double node = std::round(ob.position / dx);
            if (std::abs(ob.position / dx - node) < 1e-9 && node > 0 && node < gridIntervals)
                c.gridNode = static_cast<int>(node);
            points.push_back(c);
            continue;
        }
        const int first = std::max(1, static_cast<int>(std::ceil(ob.supportBegin() / dx - 1e-9)));
        const int last = std::min(gridIntervals - 1, static_cast<int>(std::floor(ob.supportEnd() / dx + 1e-9)));
        for (int i = first; i <= last; ++i)
        {
            const double x = i * dx;
            points.push_back({x, dx, ob.heightAt(x), ob.law, i});
        }
    }
    return points;
}

}  // namespace jawari
