#pragma once
// The string's two transverse polarisations as one modal set (docs/design.md section 1, "Two
// polarisations"). The vertical polarisation (modes 0 .. M-1) meets the obstacles; the horizontal
// one (modes M .. 2M-1: its own small detuning and damping) meets none, and takes energy only
// through a coupling: a linear spring of stiffness K at x_c whose direction d = (cos theta,
// sin theta) in the (vertical, horizontal) plane is tilted, V = (K/2) (d . w(x_c))^2 with
// w = (u_vertical, u_horizontal). A support that yields differently in the two directions (a
// termination, the thread's groove) couples the polarisations this way; theta = 0 or pi/2 couples
// nothing.
//
// The spring enters the solver as two one-sided contact points with the linear law (alpha = 1):
// K [s]_+ on the row d . phi(x_c) and on its negative, whose potentials (K/2) [s]_+^2 and
// (K/2) [-s]_+^2 add up to (K/2) s^2. The energy-conserving contact solve then conserves the
// discrete energy of the whole string, spring included, whatever K and theta. OFF.

#include "physics/modes/ModalSolver.h"

namespace jawari
{

struct PolarisationCoupling
{
    double position = 0.0;   // x_c (m)
    double angle = 0.0;      // theta (rad) from the vertical
    double stiffness = 0.0;  // K (N/m); 0: the polarisations are independent
};

struct SecondPolarisation
{
    double detuning = 0.0;       // the horizontal modes' frequencies are (1 + detuning) times the vertical's
    double dampingScale = 1.0;   // and their damping this times the vertical's
    double excitationAngle = 0.0;  // the pluck's direction (rad from the vertical): cos to one, sin to the other
    PolarisationCoupling coupling;
};

// The solver configuration of both polarisations from one polarisation's (stringSolverConfig or
// voiceSolverConfig: its modes, obstacles' contact points, pickup and excitation), M modes becoming
// 2M: the obstacles act on the vertical, the pickups read the vertical, the excitation pushes along
// excitationAngle, and the coupling adds its two points after the obstacles' (when K > 0). The
// projection path, without a residual compliance: other configurations are refused.
ModalSolverConfig twoPolarisationConfig(const ModalSolverConfig& vertical, const SecondPolarisation& second);

// The same string with the coupling spring folded into its modes: the 2M normal modes of the
// coupled linear string, the eigenvectors V of Omega^2 + (K/mu) r r^T (r = d . phi(x_c) over both
// polarisations' modes). Without losses it is the same string, its spring's energy inside the
// modes' own; each mode takes the damping its shape averages, sigma'_k = sum_p V_pk^2 sigma_p, and
// the damping's cross terms between the new modes are dropped (an approximation with losses, as
// any modal damping is). The obstacles' rows, the pickups and the excitation are carried into the
// new modes (V^T times each): a tanpura's one point keeps the solver's two-step pass. The new modes
// ascend in frequency; each column of V has its largest-magnitude component positive. OFF: Omega^2
// + (K/mu) r r^T is a diagonal plus a rank-one update, its eigenpairs from the secular equation in
// O(M^2) (RankOneEigen.h).
struct CoupledModes
{
    ModalSolverConfig config;
    std::vector<double> basis;  // V, 2M x 2M, column k the new mode k in the polarisations' modes
    // q' = V^T q: a state in the polarisations' modes (2M values) in the new ones.
    std::vector<double> fromPolarisations(const std::vector<double>& q) const;
};
CoupledModes coupledModesConfig(const ModalSolverConfig& vertical, const SecondPolarisation& second);

// The energy of modes [first, first + count) from the solver's state (J): one polarisation's
// share of the string energy (ModalSolver::stringEnergy sums every mode).
double modeRangeEnergy(ModalSolver& solver, int first, int count);

}  // namespace jawari
