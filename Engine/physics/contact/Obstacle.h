#pragma once
// Obstacles below (or pushing into) the string, and the contact points that stand for them.
// Heights are g(x) in metres; the string at rest is at 0 and heights > 0 push into it.

#include "physics/contact/ContactLaw.h"

#include <vector>

namespace jawari
{

enum class ObstacleType
{
    point,    // one contact point of weight `width` (metres of string it stands for)
    profile,  // sampled heights, linear interpolation between the samples
    parabola,  // g = height - curvature/2 (x - position)^2 over `width` centred on position
    // g = height over `width` centred on position, its points' weights shaped by the raised cosine
    // psi(x) = (pi / 2w) cos(pi (x - position) / w) of DAFx-16's forces (the damped thread)
    band
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
    // Distributed obstacles: the spacing of their contact points (m), the nodes of the grid
    // x_i = i L / round(L / spacing). 0: the contact grid's default, L / kContactGridIntervals.
    double spacing = 0.0;

    bool isDistributed() const { return type != ObstacleType::point; }
    double supportBegin() const;
    double supportEnd() const;
    // g(x) inside the support (distributed obstacles).
    double heightAt(double x) const;
    // The highest g over the support: a parabola's apex (or an edge), a profile's highest sample.
    double highestHeight() const;
};

// The tanpura's thread (jiva): a cotton thread laid across a bridge between the bridge and the
// string, which the player slides to set the jawari (docs/design.md section 1, "The thread").
enum class ThreadModel
{
    // A spring-damper over the thread's width that the string never leaves (van Walstijn, Bridges
    // & Mehes, DAFx-16): `stiffness` N/m and `damping` kg/s in all, spread by the raised cosine.
    springDamper,
    contact  // a unilateral contact point with `law`, as rigid as the bridge
};

// DAFx-16's rule for a thread `width` m wide: k = width x 1e8 N/m, and r = k x 1e-5 s, which gives
// their Table 1's 1.2 kg/s for 1.2 mm (their text prints 1e-6, which gives 0.12).
constexpr double threadStiffnessForWidth(double width) { return width * 1e8; }
inline constexpr double kThreadWidthMetres = 1.2e-3;  // their C3 string's thread
constexpr double threadDampingForStiffness(double stiffness) { return stiffness * 1e-5; }

struct Thread
{
    double offset = 0.002;      // m from the bridge's edge nearer x = 0
    double diameter = 0.2e-3;   // m: how far it lifts the string off the bridge
    ContactLaw law;             // the contact model's
    ThreadModel model = ThreadModel::contact;  // scenes default to the spring-damper (docs/scenes.md)
    double width = kThreadWidthMetres;  // m: the length of string the spring-damper holds
    double stiffness = 1.2e5;   // N/m, the spring-damper's in all
    double damping = 1.2;       // kg/s, the spring-damper's in all
};

// Lays a thread across a distributed bridge. The string rests on the highest support: the bridge is
// moved (its apex or every sample, by one amount) so that the higher of the thread's top (the
// bridge's surface there plus the diameter) and the bridge's crown lies at the string's rest line
// (height 0). The contact thread is returned as a point obstacle, its top at that height and its
// weight the diameter; the spring-damper as a band of the thread's width centred there, its law
// bilateral (stiffness and damping per metre of that width), on the bridge's contact grid. The
// spring-damper holds the string at the rest line, where the bridge's crown grazes it (DAFx-16's
// h_b = h_c = 0): its diameter is the contact model's only. Its jawari is the crown beyond it,
// between the thread and the speaking length. Where the thread is the higher, as a player sets it, its top is the rest line and the
// bridge lies `diameter` below the string there; where the crown rises above the thread (a steep
// bridge, a thread far from its apex), the string rests on the crown and the thread lies under it,
// clear of it at rest. The thread's place is begin + offset, clamped to the bridge's far edge: an
// offset of the bridge's whole width lies on it whatever the rounding. Throws std::invalid_argument
// when the bridge is not distributed or the thread lies off it (threadFitsBridge).
Obstacle layThread(Obstacle& bridge, const Thread& thread);

// The thread as an obstacle at `position` with its top at `height`, on a contact grid of `spacing`
// (0: the default grid), by its model (layThread's). Throws std::invalid_argument for a
// spring-damper without a positive width and stiffness or with a negative damping.
Obstacle threadObstacle(const Thread& thread, double position, double height, double spacing);

// Whether a thread `offset` m from the bridge's near edge lies on the bridge: 0 <= offset and
// begin + offset <= end, up to a nanometre (the rounding of begin + width against end).
bool threadFitsBridge(const Obstacle& bridge, double offset);

struct ContactPoint
{
    double position = 0.0;  // m
    double weight = 0.0;    // m of string this point stands for
    double height = 0.0;    // g at the point (m)
    ContactLaw law;
    int gridNode = -1;  // i when position is the node x_i = i L / N, else -1
};

// The contact grid a distributed obstacle is sampled on by default: the reference's grid
// (kReferenceModes + 1 intervals, 0.9 mm on the paper's string), so the reference's contact points
// are its own nodes (decoupled, docs/design.md section 2) and every voice, whatever its M, meets
// the same points.
inline constexpr int kContactGridIntervals = 1002;

// How many intervals an obstacle's contact grid has on a string of this length.
int contactGridIntervals(const Obstacle& obstacle, double lengthMetres);

// A point obstacle becomes one contact point at its position with weight `width`; a distributed
// obstacle is sampled at the interior nodes x_i = i L / Nc (0 < i < Nc) of its own contact grid
// inside its support, each of weight L / Nc: points fixed by the obstacle, not by the modes kept.
// A band's nodes (strictly inside it) weigh width psi(x_i) / sum psi, `width` in all; a band no node
// falls in is one point at its centre.
// Points that land on a node of the solver's grid x_i = i L / N (to 1e-9 of its spacing) carry
// that node's index (the transform path).
std::vector<ContactPoint> contactPointsOnGrid(const std::vector<Obstacle>& obstacles, double lengthMetres,
                                              int gridIntervals);

}  // namespace jawari
