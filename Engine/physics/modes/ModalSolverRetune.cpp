// What moves the solver's coefficients while it sounds: a retune (new frequencies and damping, the
// motion carried), the static-exact forcing's gains following it, and a contact's new law and height.
#include "physics/modes/ModalSolver.h"

#include "physics/modes/ModalKernels.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace jawari
{

void ModalSolver::retune(const double* omega, const double* sigma, double complianceScale, double pickupScale,
                         RetuneMotion motion)
{
    state_.toSingle();  // the paired layout's corrections were made with the old coefficients
    const bool moved = motion == RetuneMotion::keepActions && keepModeActions(omega, sigma);
    auto& omegas = omega_.edit();
    auto& sigmas = sigma_.edit();
    auto& coeffs = coeffs_.edit();
    auto& coeffsReleased = coeffsReleased_.edit();
    for (int p = 0; p < M_; ++p)
    {
        omegas[p] = omega[p];
        sigmas[p] = sigma[p];
        coeffs[p] = exactCoefficients(omegas[p], sigmas[p], dt_);
        coeffsReleased[p] = exactCoefficients(omegas[p], sigmas[p] + releaseSigma_, dt_);
    }
    if (!modeScale_.empty())
        followStaticGains();
    for (auto& pickup : pickups_)
        pickup.setWeights(omega_, pickupScale);
    state_.fillTables(coeffs_, coeffsReleased_, pickups_[0].weights(), pickups_[1].weights());
    for (int k = 0; k < 2; ++k)
        if (const double* h = activePickupWeights(k))
            pickups_[size_t(k)].rereadActive(h, state_, pickupForces(), !transform_);
    if (compliance_.active())
        compliance_.rescale(complianceScale, contacts_);
    if (compliance_.active() || !modeScale_.empty())
        updateCouplings();
    if (moved)
    {
        // The contact points' displacements at n and n-1, read from the modes moved (on the rows as
        // the static-exact forcing left them), and what the quadratised contact keeps of them.
        projectActive(state_.q(), uC_.data());
        projectActive(state_.qPrev(), uCPrev_.data());
        if (method_ == ContactMethod::quadratised)
            quadratised_.restart(contacts_, uC_.data(), uCPrev_.data());
        trialBefore_ = trialMove_ = std::numeric_limits<double>::quiet_NaN();
    }
    measureReach();
    reach_.markStale();  // the same motion at another pitch holds another energy
}

// A string retuned while it sounds keeps each mode's action E/omega (the adiabatic invariant of an
// oscillator whose frequency moves) at its phase, so that a pitch moving back and forth, however
// fast, returns the string to the energy it had: kept state, a retune in one phase of the motion
// adds energy and in another takes it, and retunes at the chunk rate pump a mode parametrically.
// Mode i at (x, y) = (q^n, q^{n-1}) under q^{n+1} = a q^n - e q^{n-1}, a = 2R cos(theta), e = R^2
// (R = exp(-sigma dt), theta = w_d dt), is A R^n (cos psi, cos(psi - theta) / R): its phase's sine
// part S = A R^n sin psi = (R y - x cos theta) / sin theta. At the new (R', theta') the same phase
// has y' = (x cos theta' + S sin theta') / R', and (x, y') is scaled by s so that its discrete
// energy E(x, y) = ((1+e)/2)(x^2 + y^2) - a x y (times mu / 2dt^2) is omega'/omega times the old.
// The map is homogeneous, so it holds in the static-exact forcing's coordinates p = q / sqrt(gamma)
// too, whose energy is the scheme's (the mode of mass mu / gamma): s takes the gain's change as well,
// which followStaticGains then divides out. A mode whose
// frequency stays (a new damping alone), one damped past a tenth of its motion in a step, critically
// or beyond, or within 0.14 of the step's Nyquist phase keeps its state. Returns whether any moved.
bool ModalSolver::keepModeActions(const double* omega, const double* sigma)
{
    const double extra = state_.released() ? releaseSigma_ : 0.0;
    double* q = state_.q();
    double* qPrev = state_.qPrev();
    bool moved = false;
    for (int i = 0; i < state_.activeCount(); ++i)
    {
        const int p = state_.activeMode(i);
        const double wOld = omega_[p], wNew = omega[p];
        const double sOld = sigma_[p] + extra, sNew = sigma[p] + extra;
        if (wNew == wOld || !(sOld < wOld) || !(sNew < wNew))
            continue;
        const double tOld = std::sqrt(wOld * wOld - sOld * sOld) * dt_, tNew = std::sqrt(wNew * wNew - sNew * sNew) * dt_;
        const double rOld = std::exp(-sOld * dt_), rNew = std::exp(-sNew * dt_);
        if (tOld > 3.0 || tNew > 3.0 || rOld < 0.1 || rNew < 0.1)
            continue;
        const double x = q[i], y = qPrev[i];
        const double S = (rOld * y - x * std::cos(tOld)) / std::sin(tOld);
        const double yNew = (x * std::cos(tNew) + S * std::sin(tNew)) / rNew;
        auto energy = [](double r, double t, double u, double v) {
            return 0.5 * (1.0 + r * r) * (u * u + v * v) - 2.0 * r * std::cos(t) * u * v;
        };
        const double before = energy(rOld, tOld, x, y), after = energy(rNew, tNew, x, yNew);
        if (!(before > 0.0 && after > 0.0))
            continue;
        // The static-exact forcing's gains follow (followStaticGains divides p by g'/g): its energy,
        // that of p, is kept through them.
        const double gains = modeScale_.empty() ? 1.0
                                                : std::sqrt(staticForcingGain(wNew, sigma[p], dt_)) / modeScale_[size_t(p)];
        const double scale = gains * std::sqrt(wNew / wOld * before / after);
        q[i] = scale * x;
        qPrev[i] = scale * yNew;
        moved = true;
    }
    return moved;
}

// Each mode's new sqrt(gamma_p) over its old, r_p, divides its coordinate p_p and multiplies its
// contact shapes, excitation and pickup weights: q_p = sqrt(gamma_p) p_p and every reading stay the
// same motion. The string's coupling A = (dt^2/mu) Phi Phi^T W is formed again from the new shapes
// (P^2 M products: a few tens of thousands on a voice).
void ModalSolver::followStaticGains()
{
    for (int p = 0; p < M_; ++p)
    {
        const double g = std::sqrt(staticForcingGain(omega_[p], sigma_[p], dt_));
        gainRatio_[size_t(p)] = g / modeScale_[size_t(p)];
        modeScale_[size_t(p)] = g;
    }
    state_.rescaleModes(gainRatio_.data());
    auto& shapes = shapes_.edit();
    for (int j = 0; j < P_ && !shapes.empty(); ++j)
        scaleByModes(shapes.data() + size_t(j) * M_, M_, gainRatio_);
    if (!excitationShape_.empty())
        scaleByModes(excitationShape_.edit().data(), M_, gainRatio_);
    for (auto& pickup : pickups_)
        pickup.scaleConfigured(gainRatio_.data());
    fillStringResponse(stringCoupling_);
}

void ModalSolver::updateCouplings()
{
    const bool withCompliance = compliance_.active();
    for (int i = 0; i < P_; ++i)
        for (int j = 0; j < P_; ++j)
        {
            const double a = stringCoupling_(i, j) + (withCompliance ? compliance_.coupling()(i, j) : 0.0);
            pointCoupling_(i, j) = a / contacts_[j].weight;
            couplingScratch_(i, j) = a;
        }
    system_.setCoupling(couplingScratch_);
    trialBefore_ = trialMove_ = std::numeric_limits<double>::quiet_NaN();  // a trial of the old coupling
}

void ModalSolver::setContact(int j, const ContactLaw& law, double height)
{
    const bool lawChanged = contacts_[size_t(j)].law.stiffness != law.stiffness
                            || contacts_[size_t(j)].law.exponent != law.exponent
                            || contacts_[size_t(j)].law.bilateral != law.bilateral;
    if (contacts_[size_t(j)].height != height)
        wakeAll();  // a sleeping point may now be within reach
    reach_.markStale();  // and the obstacles' energy is another
    contacts_[size_t(j)].law = solverLaw(law, dt_);
    contacts_[size_t(j)].height = height;
    system_.setLaw(j, contacts_[size_t(j)].law);
    trialBefore_ = trialMove_ = std::numeric_limits<double>::quiet_NaN();  // a trial of the old law
    findSpringPoint();
    if (method_ == ContactMethod::quadraticSpline && lawChanged && !law.bilateral)
        splines_[size_t(j)].setLaw(law);
}

// springPoint_: the one bilateral point of a string solved by the energy-conserving method with
// coupled points, else -1; springsUntried_: a string of several points with springs that is not that.
}  // namespace jawari
