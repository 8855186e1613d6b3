#pragma once
// Strings that stand on one body, each in its own solver, stepped together: the partitioned form of
// the one solver that appendString and withBody build (ModalBody.h; docs/design.md section 1,
// "Strings that share the body"), for strings that keep their own solvers (the instrument's).
//
// Every contact point of every string stands on the body's bridge, which moves by w = kappa sum_k z_k.
// Given the bridge's displacement W at n+1, each string's contact equations are its own, with every
// obstacle raised by w^{n-1} at n-1 and by W at n+1; their solution pushes the body with
// F(W) = sum_i sum_j w_j G_j. The body's modes then reach z^{n+1} = a z^n - e z^{n-1} + (dt^2 kappa / m_k) F,
// so W = w~ + beta F(W), beta = dt^2 kappa^2 sum_k 1/m_k. A step solves that one scalar equation by
// the secant method: first on trials, each string's force from the one point that pressed at its
// last step, alone (a scalar equation, nothing kept; with its spring, where it has one), then on
// contact solves of every string
// with the bridge at W (the modes' pass runs once), from the trials' answer: most steps press where
// the last one did, and one solve confirms it. The joined solver's equations, solved to rounding,
// so its energy balance. beta is small beside a string's own compliance at its points (a tanpura's
// body: a few per cent of it), so the secant converges in a few evaluations; with nothing pressing,
// F = 0 and one suffices.
//
// The points out of reach are left out of every string's solve as a string alone leaves them, from
// budgets that each step's energy balance keeps (BodyReach).

#include "physics/body/BodyReach.h"
#include "physics/modes/ExactOscillator.h"
#include "physics/body/LinearStringBank.h"
#include "physics/body/ModalBody.h"
#include "physics/modes/ModalSolver.h"

#include <array>
#include <vector>

namespace jawari
{

class SharedBody
{
public:
    // OFF: the body at rest, coupled by `coupling` (0: nothing reaches it), at its strings' common time
    // step; they solve their contacts by the energy-conserving method or the quadratic spline (check()).
    SharedBody(const ModalBody& body, double coupling, double timeStep);
    // OFF: checks that a string can stand on the body (throws std::invalid_argument naming why not).
    void check(const ModalSolver& string) const;
    // OFF: check(), and every contact point a spring (bilateral): a string whose force is affine in W.
    void checkLinear(const ModalSolver& string) const;
    // Whether every contact point of the string is a spring (bilateral).
    static bool standsOnSprings(const ModalSolver& string);

    // RT: one step of `count` strings and of the body. An explicit force on a string is part of its
    // prediction. The strings from `split` on (the sympathetic strings) drive a copy of the body's
    // modes of their own: the body is linear, so partPressure() is their share of pressure() (split =
    // count: none, and the copy is not stepped). Where every contact point of theirs is a spring
    // (standsOnSprings), their force is affine in the bridge's displacement: measured twice a step and
    // solved once more at the answer, not at every secant evaluation. Where one can leave a point (a
    // sympathetic string's jawari), they are solved with the played strings.
    void step(ModalSolver* const* strings, int count, int split);
    void step(ModalSolver* const* strings, int count) { step(strings, count, count); }

    // OFF or RT: one way (a comparison, not the instrument's physics): the strings stand on rigid
    // supports and their forces there drive the body, which moves nothing back (one contact solve a
    // step; the sympathetic strings then stay at rest). Off by default: two way.
    void setOneWay(bool oneWay)
    {
        oneWay_ = oneWay;
        reach_.chooseAgain();
    }
    bool oneWay() const { return oneWay_; }

    // OFF or RT: a delayed link (a comparison, not the instrument's physics; docs/design.md, "A delayed
    // link, for comparison"): each string meets the body through a lossless line of its own, of
    // impedance R (kg/s), whose waves take one step from end to end. Each string's bridge is then a
    // massless node of its own held by its line, the body's bridge is held by every line, and neither
    // side needs the other's force within the step: the connection through wave variables that would
    // let strings step apart. 0, the default: the rigid bridge solved within the step. Starts with
    // the lines at rest and each node where the bridge is. Linked, every string is solved with every
    // point live, one way is ignored and partPressure() is not kept. At most kMostLinked strings
    // (step() throws beyond).
    void setDelayedLink(double impedance);
    // RT: the waves in transit on the first `count` strings' delayed links (J; part of energy()).
    double lineEnergy(int count) const;
    static constexpr int kMostLinked = BodyReach::kMostStrings;

    double bridgeDisplacement() const { return bridge_; }  // RT: w^n (m)
    double lastBridgeForce() const { return force_; }  // RT: F of the last step (N, < 0 pushing the body down)
    // Where the two channels hear the body (ModalBody::listeners). RT, no allocation.
    // listenAt: both at one listener. listenBetween: the left channel between the first listener
    // (width 0) and the second (1), the right between the first and the third, each mode's weight
    // scaled so that the power near its frequency keeps the listeners' (BodyMode::correlation);
    // with fewer than three listeners both hear the first. By default both hear the first.
    void listenAt(int listener);
    void listenBetween(double width);
    // RT: the radiated pressure at a channel (0 left, 1 right) at t^n, the step before the last one
    // stepped: sum_k g_k (z_k^{n+1} - z_k^{n-1}) / (2 dt) with the channel's weights g (Pa).
    double pressure(int channel) const { return pressure_[size_t(channel)]; }
    // RT: the same from the forces of the strings after split.
    double partPressure(int channel) const { return partPressure_[size_t(channel)]; }
    // RT: the strings from `from` to `to` (the sympathetic strings, after split) stepped as one
    // LinearStringBank from the next step() on, their solvers untouched (not to be read) until
    // unbankLinear() gives their state back. False, and nothing taken, unless every one is held by a
    // lone spring (LinearStringBank::fits), the bridge is solved within the step (two way, no delayed
    // link) and they are at most LinearStringBank::kLanes. step() must then be given the same strings,
    // with split = from and count = to. Their motion is their own solvers' to rounding (single steps
    // where alone they pair them), and the energy balance theirs.
    bool bankLinear(ModalSolver* const* strings, int from, int to);
    void unbankLinear(ModalSolver* const* strings);
    bool banked() const { return banked_; }

    // RT: whether step() keeps partPressure() (by default it does). Not kept, the copy of the modes
    // rests and partPressure() is 0: a caller that does not hear the share spares the copy's pass.
    // Kept again, the copy starts from rest, so until the body's modes have rung out the share misses
    // what the strings after split put in while it rested.
    void keepPart(bool keep);
    // RT: the last step's rounds of solves at a bridge found (each string still on its trial solved
    // once: most often that trial, kept), and its evaluations of the bridge's equation (each string
    // by its trial, ModalSolver::trialOnMovingBridge, or by its solve where it has none).
    int lastEvaluations() const { return evaluations_; }
    int lastTrials() const { return trials_; }
    bool atRest() const;                               // RT: every mode below 1e-18 m
    // RT: the body's modes' part of the joined H^{n-1/2} (J); with the strings' energyOnBridge() at
    // bridgeDisplacement() and the one before, the whole. No allocation.
    double bodyEnergy() const;
    // RT: the joined energy of the body and `count` strings (not while some are banked: their solvers
    // hold the state they had when the bank took them).
    double energy(const ModalSolver* const* strings, int count) const;
    // RT: whether the last step was solved again with every point live (BodyReach).
    bool lastResolved() const { return resolved_; }
    void silence();                                    // RT: every mode at rest
    // RT: a body built anew takes the motion of the one it replaces (a pack rebuilt while the strings
    // sound): the same body (the same modes, coupling and step) its whole state; another, only the
    // bridge's displacement at n and n-1, spread over its modes by their static compliance
    // (z_k = w kappa c_k / sum_j kappa^2 c_j, c_k = 1 / (m_k C2_k)), so the strings pressing on the
    // bridge find it where it was. No allocation.
    void takeMotionFrom(const SharedBody& other);

private:
    double solveForce(ModalSolver* const* strings, int from, int to, double before, double bridge);
    double trialForce(ModalSolver* const* strings, int from, int to, double before, double bridge,
                      double* slope = nullptr) const;
    double evaluate(ModalSolver* const* strings, double before, double bridge);
    void fitLinear(ModalSolver* const* strings, double before, double at);
    double solveBridge(ModalSolver* const* strings, double before, double predicted);
    template <typename ResidualOf, typename Tolerance>
    double secantOnStrings(ModalSolver* const* strings, int n, int split, double before, double w,
                           ResidualOf&& residualOf, Tolerance&& tolerance, double& slope, double& played, double& part);
    void stepPart(double partForce);
    void finishBody(double predicted, const double* read);
    void stepLinked(ModalSolver* const* strings, int count, double predicted);
    double solveNode(ModalSolver& string, double before, double arriving, double& node);
    void pushHeard();
    void pressuresFrom(const double* moved, double force, std::array<double, 2>& out) const;

    // Per mode: the exact update's a and e, dt^2 kappa / m_k, kappa (the bridge reads sum kappa z_k),
    // z^n and z^{n-1} (the prediction is written over z^{n-1}, then swapped in).
    std::vector<double> a_, e_, push_, kappa_;
    std::array<std::vector<double>, kMostListeners> weights_;  // c_k at each listener
    std::array<std::vector<double>, 2> sideCorrelation_;      // per mode: BodyMode::correlation[1], [2]
    std::array<std::vector<double>, 2> heard_;                // the channels' weights g_k
    std::array<double, 2> heardPush_{};                       // sum_k g_k dt^2 kappa / m_k per channel
    int channels_ = 1;       // 1: both channels hear the same weights (read once)
    int heardListener_ = 0;  // with one channel, the listener both hear
    double width_ = 0.0;    // what listenBetween was last given
    std::vector<double> z_, zPrevious_;
    std::vector<double> kinetic_, potential_;  // per mode, m_k C1 / (2 dt^2) and m_k C2 / 2: its energy's weights
    BodyReach reach_;
    std::array<double, BodyReach::kMostStrings> forces_{};  // each string's force at the last solve (N)
    // secantOnStrings: each string's trial force at the last evaluation (N), and whether it is solved
    // at every evaluation for the rest of the step.
    std::array<double, BodyReach::kMostStrings> trialForces_{};
    std::array<char, BodyReach::kMostStrings> solvedNow_{};
    bool resolved_ = false;
    std::vector<double> zPart_, zPartPrevious_;  // the copy driven by the strings after split alone
    bool partKept_ = true;
    LinearStringBank bank_;
    bool banked_ = false;
    int bankFrom_ = 0;
    double dt_ = 0.0, beta_ = 0.0, force_ = 0.0;
    double bridge_ = 0.0, bridgeBefore_ = 0.0;             // w^n, w^{n-1}
    std::array<double, 2> pressure_{}, partPressure_{};     // per channel (Pa)
    double partForce_ = 0.0;                                // the strings' after split_
    int listeners_ = 1;  // the body's
    double playedForce_ = 0.0;  // the strings' before linearFrom_, at the last evaluation
    double linearForce_ = 0.0, linearSlope_ = 0.0, linearAt_ = 0.0;  // the affine fit: F, dF/dW at W
    int split_ = 0, count_ = 0;
    int linearFrom_ = 0;  // split_ if every string after it stands on springs (affine in W), else count_
    bool oneWay_ = false;
    // A string's end of its delayed link: its node's displacement w^n and w^{n-1} (m), and the waves
    // sent at the last step (N), to arrive at the string's end and at the body's at the next.
    struct LinkEnd
    {
        double node = 0.0, nodeBefore = 0.0;
        double toString = 0.0, toBody = 0.0;
    };
    std::array<LinkEnd, kMostLinked> links_{};
    double linkImpedance_ = 0.0;
    double slope_ = 1.0;  // R'(W) as the last secant measured it
    int evaluations_ = 0, trials_ = 0;
};

}  // namespace jawari
