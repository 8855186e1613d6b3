#pragma once
// Obstacles below (or pushing into) the string, and the contact points that stand for them.
// Heights are g(x) in metres; the string at rest is at 0 and heights > 0 push into it.

#include "physics/ContactLaw.h"

#include <vector>

namespace jawari
{

enum class ObstacleType
{
    point,    // one contact point of weight `width` (metres of string it stands for)
    profile,  // sampled heights, linear interpolation between the samples
    parabola  // g = height - curvature/2 (x - position)^2 over `width` centred on position
};

struct Obstacle
{
    ObstacleType type = ObstacleType::point;
    ContactLaw law;
    double position = 0.501;            // point: where; parabola: apex (m)
    double height = 0.0;                // point, parabola apex (m)
    double width = 1e-3;                // point: weight; parabola: extent (m)
    double curvature = 0.0;             // parabola, 1/m
    std::vector<double> profileX;       // profile sample positions, strictly increasing (m)
    std::vector<double> profileHeight;  // profile heights (m)

    bool isDistributed() const { return type != ObstacleType::point; }
    double supportBegin() const;
    double supportEnd() const;
    // g(x) inside the support (distributed obstacles).
    double heightAt(double x) const;
};

struct ContactPoint
{
    double position = 0.0;  // m
    double weight = 0.0;    // m of string this point stands for
    double height = 0.0;    // g at the point (m)
    ContactLaw law;
    int gridNode = -1;  // i when position is the node x_i = i L / N, else -1
};

// A point obstacle becomes one contact point at its position with weight `width`; a distributed
// obstacle is sampled at the interior nodes x_i = i L / N (0 < i < N) inside its support, each of
// weight dx = L / N. Points that land on a node (to 1e-9 dx) carry that node's index.
std::vector<ContactPoint> contactPointsOnGrid(const std::vector<Obstacle>& obstacles, double lengthMetres,
                                              int gridIntervals);

}  // namespace jawari
