#pragma once
// One pickup's reading of the string's modes (docs/design.md section 2): y^n = sum_p h_p q_p^n, and
// within a step what the forces add to it,
//
//   y~      = h . q~                                   (the contact-free prediction's reading)
//   y^{n+1} = y~ - sum_j (dt^2/mu) w_j (h . phi_j) G_j  (+ (dt^2/mu) F (h . phi_e) for a pluck force F).
//
// Above the pickup band (ModalSolverConfig::pickupBandHz) a mode is read not as it moves but by its
// static response to the forces: a force held still on a shape s moves mode p by (dt^2/mu) s_p /
// (1 - a_p + e_p) per newton, the fixed point of q = a q - e q + (dt^2/mu) s. Its ringing is above what
// the voice's decimator passes. Between the band and 1.25 times it each mode is read by a share of
// each, linear in its frequency, so a pitch bend carries a mode across without a step.
//
// The solver keeps one per pickup (the instrument's two channels); a pickup without weights reads 0.

#include "physics/modes/ExactOscillator.h"
#include "physics/contact/Obstacle.h"
#include "physics/modes/StampedVector.h"

#include <vector>

namespace jawari
{

class ModalState;

class PickupReadout
{
public:
    // What the forces act through, for the pickup's response to them: the contact points' and the
    // excitation's shapes over every mode (P x M row-major, and M values or empty), the points,
    // (dt^2/mu) and the modes' coefficients (the static response's 1 - a_p + e_p).
    struct Forces
    {
        const std::vector<double>& contactShapes;
        const std::vector<double>& excitationShape;
        const std::vector<ContactPoint>& contacts;
        double forceScale;
        const std::vector<ExactModeCoefficients>& coefficients;
    };

    // OFF: the base weights h_p of the model's `modes` modes (fewer: the rest 0; empty: no pickup),
    // read as they move up to `bandOmega` (rad/s; 0: every mode), for `points` contact points.
    void configure(const std::vector<double>& weights, int modes, double bandOmega, int points);
    bool present() const { return !base_.empty(); }

    // RT: the weights in use for the modes' frequencies omega (rad/s): `scale` times the base ones,
    // split into the share read as the modes move (weights()) and the share read statically.
    void setWeights(const std::vector<double>& omega, double scale);
    // RT: the configured weights, mode by mode, times ratio[p] (the static-exact forcing's new
    // sqrt(gamma_p) over its old); setWeights() then applies them.
    void scaleConfigured(const double* ratio);
    const std::vector<double>& weights() const { return weights_; }  // every mode (empty: no pickup)

    // OFF: the responses to a force at each point and at the excitation, with the weights over every mode.
    void readForces(const Forces& forces);
    // RT: the responses again with the weights `h` over the active modes in the state's arrays (at the
    // points only with `atPoints`: not on the transform path), and read().
    void rereadActive(const double* h, const ModalState& state, const Forces& forces, bool atPoints);
    // RT: value = h . q^n with the weights `h` over the active modes (null: no pickup, 0).
    void read(const double* h, const ModalState& state);

    // sum over the modes above the band of their static share of h_p shape_p / (1 - a_p + e_p).
    double staticResponse(const double* shape, const std::vector<ExactModeCoefficients>& coefficients) const;
    // RT: what the moving reading leaves out of the modes above the band as they are now.
    double aboveBand(const ModalState& state) const;
    // OFF: sum_p h_p^2 / (mu w_p^2), every weight in full: |y| <= sqrt(2 H this) for a string of energy H.
    double compliance(double mu, const std::vector<double>& omega) const;

    // RT, within a step: the prediction's reading corrected by point j's force slope G_j (f_j = -G_j)
    // and by an external force (N) at the excitation.
    void press(int j, double slope) { predicted -= atPoint_[size_t(j)] * slope; }
    double responseAt(int j) const { return atPoint_[size_t(j)]; }  // what press(j, 1) takes off
    void push(double newtons) { predicted += newtons * atExcitation_; }

    double value = 0.0;      // y^n
    double predicted = 0.0;  // y~ of the step under way, then corrected by its forces

private:
    StampedVector<double> base_;     // h_p, every mode
    StampedVector<double> weights_;  // the share read as the modes move, scale_ included
    // The share read statically, (1 - moving share) scale_ h_p; empty without a band.
    StampedVector<double> static_;
    double scale_ = 1.0;
    double bandOmega_ = 0.0;       // rad/s; 0: every mode moves
    std::vector<double> atPoint_;  // (dt^2/mu) w_j (h . phi_j) per point, static response included
    double atExcitation_ = 0.0;    // (dt^2/mu) h . phi_e
};

}  // namespace jawari
