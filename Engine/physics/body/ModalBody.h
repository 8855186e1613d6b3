#pragma once
// The instrument's body under the bridge as a set of modes (docs/design.md section 1, "The body"),
// and how it joins the strings' solver.
//
// Mode k moves the bridge by z_k (m): the bridge's displacement is w = sum_k z_k, and a force F on
// the bridge drives each mode as m_k (z_k'' + 2 sigma_k z_k' + omega_k^2 z_k) = F, m_k its mass at
// the bridge (kg). So the bridge's mobility is Y(w) = sum_k i w / (m_k (omega_k^2 - w^2 + 2 i sigma_k w)).
// The sound radiated to a listener is p = sum_k c_k z_k' (Pa): c_k the mode's radiation weight there,
// the pressure its bridge velocity makes at that listener (a body has up to three listeners, the
// first where its response was measured). A plate above its coincidence frequency radiates as its
// surface moves, p ~ rho_air c_air v; below it the weights carry the radiation's efficiency. Read from
// the accelerations instead, a truncated modal sum passes the bridge force's whole spectrum to the
// listener however far above its last mode (each mode's instant response F / m_k); from the
// velocities, the response falls above the last mode.
//
// In the solver the body's modes are more modes beside the strings', scaled to the strings' mass per
// metre mu: zeta_k = sqrt(m_k / mu) z_k, so that (mu/2) zeta_k'^2 is the mode's kinetic energy. An
// obstacle that stands on the body moves with the bridge, so its contact points see the string's
// displacement less the bridge's: their rows gain -sqrt(mu / m_k) on mode k, and the contact force
// that pushes the string up pushes the body down by the same amount. The energy-conserving contact
// solve then conserves the discrete energy of strings, body and contact together, whatever the
// coupling. Everything here is OFF.

#include "physics/modes/ModalSolver.h"

#include <array>
#include <stdexcept>
#include <string>
#include <vector>

namespace jawari
{

inline constexpr int kMostListeners = 3;

struct BodyMode
{
    double frequencyHz = 0.0;
    double sigma = 0.0;   // 1/s
    double massKg = 0.0;  // m_k at the bridge
    // c_k at each of the body's listeners, Pa per m/s of the mode's velocity at the bridge.
    std::array<double, kMostListeners> radiation{};
    // How alike the weights at each listener are to the first's over the modes near this one's
    // frequency (each mode weighted by its share of the response's power): a mix of the first and
    // another listener divides by the mix's power there (SharedBody::listenBetween). 1: alike.
    std::array<double, kMostListeners> correlation{1.0, 1.0, 1.0};
};

struct ModalBody
{
    std::string name;  // a factory body's name, or empty
    // Where the radiated sound is heard: one name per listener (the first: where the body's response
    // was measured). The modes' radiation weights beyond these are 0.
    std::vector<std::string> listeners{"centre"};
    std::vector<BodyMode> modes;
};

// The index of the body's listener called `name`, or -1.
int listenerIndex(const ModalBody& body, const std::string& name);

// What the body adds to a solver: its modes after the strings', and which contact points stand on it.
struct BodyJoin
{
    const ModalBody* body = nullptr;
    std::vector<char> pointOnBody;  // per contact point of the strings' configuration
    // Scales every mode's coupling row (0: the body is there but nothing reaches it; 1: as measured).
    double coupling = 1.0;
    // Give the strings' configuration a pluck map (ModalSolverConfig::shapeToModes) when it has none:
    // the identity on the strings' sine modes, the body at rest (a voice plucks through it).
    bool mapShapes = false;
};

// Another string beside those of `c` (sharing a body with them, ModalBody above): its modes appended
// after c's, its coordinates scaled to c's mass per metre as the body's are (q' = sqrt(mu_o / mu) q,
// rows phi sqrt(mu / mu_o)), its contact points after c's. The pickups and the excitation read and
// push c's strings only. Both on the projection path, without a residual compliance.
void appendString(ModalSolverConfig& c, const ModalSolverConfig& other);

// Per contact point of contactPointsOnGrid(obstacles, L, gridIntervals), in its order: whether its
// obstacle stands on the body (onBody: one flag per obstacle).
std::vector<char> contactPointsOnBody(const std::vector<Obstacle>& obstacles, const std::vector<char>& onBody,
                                      double lengthMetres, int gridIntervals);

// The strings' configuration (M modes, on the projection path: sine modes or their own contact rows)
// with the body's K modes appended (M + K modes): the contact rows of the points on the body take
// -coupling sqrt(mu/m_k) on mode k, the pickups and excitation read and push the strings only, the
// pluck's map leaves the body at rest. The transform path is refused (the body couples the points).
ModalSolverConfig withBody(const ModalSolverConfig& strings, const BodyJoin& join);

// The pickup weights (M + K values) that read sum_k c_k z_k at the listener: the radiated pressure
// there is their time derivative (the centred difference over two steps). Throws
// std::invalid_argument for a listener the body lacks, as bodyResponse does.
std::vector<double> radiationWeights(const ModalBody& body, int stringModes, double linearDensity, int listener = 0);

// The bridge's mobility Y(f) and the radiated pressure per newton on the bridge, P(f) = sum_k c_k i w
// / (m_k (omega_k^2 - w^2 + 2 i sigma_k w)) at the listener, at frequency f (Hz): the body's own
// responses.
struct BodyResponse
{
    double mobilityReal = 0.0, mobilityImag = 0.0;  // s/kg
    double pressureReal = 0.0, pressureImag = 0.0;  // Pa/N
};
BodyResponse bodyResponse(const ModalBody& body, double frequencyHz, int listener = 0);

// The ranges within which a body plays, in the reference and in the voice alike (docs/scenes.md):
// - a mode rings: 0 < f <= kBodyHighestHz (far above hearing and any body's measured response), and
//   its damping at most critical, sigma <= omega (past it the mode is no resonance: a mode fitted to a
//   measured response, a pair of complex poles -sigma +- i w_d, always has sigma < omega);
// - its mass at the bridge between kBodyLightestKg (a microgram: lighter than any string's metre) and
//   kBodyHeaviestKg, and the coupling at most kBodyStrongestCoupling (a body 1e4 times lighter at the
//   bridge than described): the coupling c makes each mode c^2 lighter, and its contact rows grow as
//   c sqrt(mu/m_k) until the body's part of the contact system swamps the string's within a double's
//   rounding and the solve no longer resolves the string (measured on the paper's string at 6 mm: both
//   methods play 1e-14 kg at the bridge; the voice runs away at 1e-21, the tanpura body at c = 1e10);
// - its radiation weights |c_k| <= kBodyLoudestRadiation Pa s/m (a plane wave's rho c is 413).
inline constexpr double kBodyHighestHz = 1e5;
inline constexpr double kBodyLightestKg = 1e-9;
inline constexpr double kBodyHeaviestKg = 1e6;
inline constexpr double kBodyStrongestCoupling = 100.0;
inline constexpr double kBodyLoudestRadiation = 1e6;

// A body's mode out of its range: which mode, which field (its name in a scene: "frequency",
// "damping", "mass", "radiation", "correlation"), and what it must be ("must be within ...").
struct BodyRangeError : std::invalid_argument
{
    BodyRangeError(int modeIndex, std::string fieldName, std::string requirementText)
        : std::invalid_argument("mode " + std::to_string(modeIndex) + ": its " + fieldName + " " + requirementText)
        , mode(modeIndex)
        , field(std::move(fieldName))
        , requirement(std::move(requirementText))
    {
    }
    int mode;
    std::string field;
    std::string requirement;
};

// Checks a body's modes (each within the ranges above) and listeners (1 to kMostListeners, named,
// no name twice); throws BodyRangeError for a mode, std::invalid_argument for the listeners.
void validateBody(const ModalBody& body);

// The largest factor every mode's damping may be scaled by and stay within critical damping
// (infinity for a lossless body).
double largestDampingScale(const ModalBody& body);

}  // namespace jawari
