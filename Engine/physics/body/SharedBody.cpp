#include "physics/body/SharedBody.h"

#include "physics/modes/ModalKernels.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

namespace jawari
{

SharedBody::SharedBody(const ModalBody& body, double coupling, double timeStep)
    : dt_(timeStep), listeners_(int(body.listeners.size()))
{
    validateBody(body);
    if (!(std::isfinite(coupling) && coupling >= 0.0) || !(timeStep > 0.0))
        throw std::invalid_argument("a shared body needs a finite coupling >= 0 and a time step > 0");
    double inverseMass = 0.0;
    for (const auto& mode : body.modes)
    {
        const auto c = exactCoefficients(2.0 * std::numbers::pi * mode.frequencyHz, mode.sigma, dt_);
        a_.push_back(c.a);
        e_.push_back(c.e);
        push_.push_back(dt_ * dt_ * coupling / mode.massKg);
        kappa_.push_back(coupling);
        kinetic_.push_back(0.5 * mode.massKg * c.kineticWeight / (dt_ * dt_));
        potential_.push_back(0.5 * mode.massKg * c.potentialWeight);
        for (int l = 0; l < listeners_; ++l)
            weights_[size_t(l)].push_back(mode.radiation[size_t(l)]);
        sideCorrelation_[0].push_back(mode.correlation[1]);
        sideCorrelation_[1].push_back(mode.correlation[2]);
        inverseMass += 1.0 / mode.massKg;
    }
    heard_ = {weights_[0], weights_[0]};
    listenAt(0);
    beta_ = dt_ * dt_ * coupling * coupling * inverseMass;
    z_.assign(body.modes.size(), 0.0);
    zPrevious_ = zPart_ = zPartPrevious_ = z_;
}

void SharedBody::check(const ModalSolver& string) const
{
    if (string.timeStep() != dt_)
        throw std::invalid_argument("a shared body's strings step at its time step");
    const auto method = string.contactMethod();
    if (string.contactCount() > 0 && method != ContactMethod::energyConserving
        && method != ContactMethod::quadraticSpline)
        throw std::invalid_argument("a shared body's strings solve their contacts by the energy-conserving method "
                                    "or the quadratic spline");
}

void SharedBody::checkLinear(const ModalSolver& string) const
{
    check(string);
    if (!standsOnSprings(string))
        throw std::invalid_argument("a shared body's linear strings touch it through springs (bilateral points) only");
}

bool SharedBody::atRest() const
{
    auto still = [](const std::vector<double>& z) {
        return std::all_of(z.begin(), z.end(), [](double x) { return std::abs(x) < 1e-18; });
    };
    return still(z_) && still(zPrevious_) && still(zPart_) && still(zPartPrevious_);
}

void SharedBody::silence()
{
    for (auto* z : {&z_, &zPrevious_, &zPart_, &zPartPrevious_})
        std::fill(z->begin(), z->end(), 0.0);
    force_ = bridge_ = bridgeBefore_ = playedForce_ = 0.0;
    links_.fill({});
    pressure_.fill(0.0);
    partPressure_.fill(0.0);
    if (banked_)
        bank_.silence();
    reach_.chooseAgain();  // the bridge's jump to rest may bring the strings' obstacles nearer
}

void SharedBody::takeMotionFrom(const SharedBody& other)
{
    if (other.banked_ || banked_)
        return;  // a bank holds the sympathetic strings' state between a chunk's steps only
    reach_.chooseAgain();
    if (a_ == other.a_ && e_ == other.e_ && push_ == other.push_)
    {
        std::copy(other.z_.begin(), other.z_.end(), z_.begin());
        std::copy(other.zPrevious_.begin(), other.zPrevious_.end(), zPrevious_.begin());
        std::copy(other.zPart_.begin(), other.zPart_.end(), zPart_.begin());
        std::copy(other.zPartPrevious_.begin(), other.zPartPrevious_.end(), zPartPrevious_.begin());
        force_ = other.force_;
        playedForce_ = other.playedForce_;
        bridge_ = other.bridge_;
        bridgeBefore_ = other.bridgeBefore_;
        pressure_ = other.pressure_;
        partPressure_ = other.partPressure_;
        return;
    }
    silence();
    // The bridge's static compliance sum_j kappa_j^2 c_j, c_j = 1 / (m_j C2_j) = 1 / (2 potential_j).
    double compliance = 0.0;
    for (size_t k = 0; k < z_.size(); ++k)
        compliance += kappa_[k] * kappa_[k] / (2.0 * potential_[k]);
    if (!(compliance > 0.0))
        return;  // nothing reaches this body: its bridge never moves
    for (size_t k = 0; k < z_.size(); ++k)
    {
        const double share = kappa_[k] / (2.0 * potential_[k]) / compliance;
        z_[k] = share * other.bridge_;
        zPrevious_[k] = share * other.bridgeBefore_;
    }
    bridge_ = other.bridge_;
    bridgeBefore_ = other.bridgeBefore_;
}

double SharedBody::bodyEnergy() const
{
    double sum = 0.0;
    for (size_t k = 0; k < z_.size(); ++k)
    {
        const double d = z_[k] - zPrevious_[k];
        sum += kinetic_[k] * d * d + potential_[k] * z_[k] * zPrevious_[k];
    }
    return sum;
}

double SharedBody::energy(const ModalSolver* const* strings, int count) const
{
    double sum = bodyEnergy();
    if (linkImpedance_ > 0.0)
    {
        for (int i = 0; i < std::min(count, kMostLinked); ++i)
            sum += strings[i]->energyOnBridge(links_[size_t(i)].node, links_[size_t(i)].nodeBefore);
        return sum + lineEnergy(count);
    }
    for (int i = 0; i < count; ++i)
        sum += strings[i]->energyOnBridge(bridge_, bridgeBefore_);
    return sum;
}

bool SharedBody::standsOnSprings(const ModalSolver& string)
{
    for (int j = 0; j < string.contactCount(); ++j)
        if (!string.contact(j).law.bilateral)
            return false;
    return true;
}

// The force at W of strings [from, to), each solved with the bridge there (and keeping that solve).
double SharedBody::solveForce(ModalSolver* const* strings, int from, int to, double before, double bridge)
{
    double force = 0.0;
    for (int i = from; i < to; ++i)
    {
        const double f = strings[i]->solveOnMovingBridge(before, bridge - before);
        if (i < BodyReach::kMostStrings)
            forces_[size_t(i)] = f;
        force += f;
    }
    return force;
}

// The same by trials (ModalSolver::trialOnMovingBridge; exact for a string with one point): NaN if
// one has none. `slope` (optional): dF/dW, NaN unless every trial has it in closed form.
double SharedBody::trialForce(ModalSolver* const* strings, int from, int to, double before, double bridge,
                              double* slope) const
{
    double force = 0.0, dForce = 0.0, one = 0.0;
    for (int i = from; i < to; ++i)
    {
        force += strings[i]->trialOnMovingBridge(before, bridge - before, slope != nullptr ? &one : nullptr);
        dForce += one;
    }
    if (slope != nullptr)
        *slope = dForce;
    return force;
}

// One way: the strings before linearFrom_ solved with the bridge at W, their force playedForce_ (the
// played strings, and those after split when they are not linear, whose share is partForce_).
double SharedBody::evaluate(ModalSolver* const* strings, double before, double bridge)
{
    playedForce_ = solveForce(strings, 0, split_, before, bridge);
    if (linearFrom_ > split_)
    {
        partForce_ = solveForce(strings, split_, linearFrom_, before, bridge);
        playedForce_ += partForce_;
    }
    return playedForce_;
}

// Every point of a linear string is a spring, so its force is affine in W: measured at one
// displacement with its slope in closed form by trials where they are exact (else at two, by
// solves), it needs no solve per secant evaluation.
void SharedBody::fitLinear(ModalSolver* const* strings, double before, double at)
{
    constexpr double kStep = 1e-9;  // m: any step measures an affine force; this one keeps rounding small
    linearAt_ = at;
    if (banked_)
    {
        linearForce_ = bank_.force(before, at - before, &linearSlope_);
        return;
    }
    linearForce_ = trialForce(strings, linearFrom_, count_, before, at, &linearSlope_);
    if (std::isfinite(linearForce_) && std::isfinite(linearSlope_))
        return;
    linearForce_ = solveForce(strings, linearFrom_, count_, before, at);
    linearSlope_ = (solveForce(strings, linearFrom_, count_, before, at + kStep) - linearForce_) / kStep;
}

namespace
{
// R(W) and, where every string's trial has it in closed form, R'(W) (else NaN).
struct Residual
{
    double value = 0.0;
    double slope = std::numeric_limits<double>::quiet_NaN();
};

// The secant on R(W) from w0 (whose residual is r0): the next W from `slope` (R' as last measured,
// renewed by each step), then from the last two; Newton's step wherever R' is known. Stops at a
// residual within tolerance(W), one that no longer moves, or when `evaluations` (of R, counted
// here) reaches `most`.
template <typename ResidualOf, typename Tolerance>
double secant(ResidualOf&& residual, Tolerance&& tolerance, double w0, Residual r0, double& slope, int& evaluations,
              int most)
{
    if (std::abs(r0.value) <= tolerance(w0))
        return w0;
    if (std::isfinite(r0.slope))
        slope = r0.slope;
    double w1 = w0 - r0.value / slope;
    while (true)
    {
        const Residual r1 = residual(w1);
        ++evaluations;
        if (std::abs(r1.value) <= tolerance(w1) || r1.value == r0.value || evaluations >= most)
            return w1;
        const double s = std::isfinite(r1.slope) ? r1.slope : (r1.value - r0.value) / (w1 - w0);
        if (std::isfinite(s) && s > 0.5)  // R' = 1 - beta F' >= 1: F falls as the bridge rises into the strings
            slope = s;
        w0 = w1;
        r0 = r1;
        w1 -= r1.value / slope;
    }
}
}  // namespace

// The root W of R(W) = residualOf(W, F(W), F'(W)), F the summed force of strings [0, n) with the
// bridge at W (those before `split` first, then the rest: played and part): the secant from w, each
// string answering at each W by its trial where it has one (ModalSolver::trialOnMovingBridge: its
// last lone presser alone, nothing solved) and by its solve where it has none, or where its solve
// once disagreed with its trial. Then the strings still on trials are solved at the W found: most
// often each solve is its trial kept, and W stands; where one is not, that string is solved from
// then on and the secant goes on. At most 16 evaluations, counted into trials_, and the rounds of
// solves that confirm into evaluations_. The strings keep the solve of the W returned; `played` and
// `part` are their forces there, and forces_ each one's.
template <typename ResidualOf, typename Tolerance>
double SharedBody::secantOnStrings(ModalSolver* const* strings, int n, int split, double before, double w,
                                   ResidualOf&& residualOf, Tolerance&& tolerance, double& slope, double& played,
                                   double& part)
{
    constexpr int kMostEvaluations = 16;
    const int tracked = std::min(n, BodyReach::kMostStrings);  // strings beyond are solved at every evaluation
    std::fill_n(solvedNow_.begin(), tracked, char(0));
    auto at = [&](double x) {
        played = part = 0.0;
        double dForce = 0.0;
        for (int i = 0; i < n; ++i)
        {
            double f = std::numeric_limits<double>::quiet_NaN(), d = 0.0;
            if (i < tracked && !solvedNow_[size_t(i)])
            {
                f = strings[i]->trialOnMovingBridge(before, x - before, &d);
                solvedNow_[size_t(i)] = std::isnan(f);
                trialForces_[size_t(i)] = f;
            }
            if (std::isnan(f))
            {
                f = strings[i]->solveOnMovingBridge(before, x - before);
                d = strings[i]->solvedForceSlope();
                if (i < tracked)
                    forces_[size_t(i)] = f;
            }
            (i < split ? played : part) += f;
            dForce += d;
        }
        return residualOf(x, played + part, dForce);
    };
    int evaluations = 1;
    Residual r = at(w);
    while (true)
    {
        w = secant(at, tolerance, w, r, slope, evaluations, kMostEvaluations);
        bool confirmed = true;
        for (int i = 0; i < tracked; ++i)
            if (!solvedNow_[size_t(i)])
            {
                const double f = strings[i]->solveOnMovingBridge(before, w - before);
                forces_[size_t(i)] = f;
                if (f != trialForces_[size_t(i)])
                {
                    (i < split ? played : part) += f - trialForces_[size_t(i)];
                    solvedNow_[size_t(i)] = 1;
                    confirmed = false;
                }
            }
        ++evaluations_;
        if (confirmed || evaluations >= kMostEvaluations)
            break;
        r = residualOf(w, played + part, std::numeric_limits<double>::quiet_NaN());
        if (std::abs(r.value) <= tolerance(w))
            break;
    }
    trials_ += evaluations;
    return w;
}

// W^{n+1}: the root of R(W) = W - w~ - beta F(W) (secantOnStrings), from the W that solves it with
// the played strings' force as the last step left it (and the linear strings' affine force), and
// the last step's slope R'. Most steps press where the last one did: the trials find W and one solve
// of each string confirms it. Stops when the residual is rounding's share of the bridge's motion;
// the played strings keep the solve of the last W, and playedForce_ is theirs.
double SharedBody::solveBridge(ModalSolver* const* strings, double before, double predicted)
{
    auto tolerance = [&](double w) { return 1e-14 * (std::abs(w) + std::abs(predicted - before)) + 1e-30; };
    const bool linear = linearFrom_ < count_;
    if (linear)
        fitLinear(strings, before, predicted + beta_ * force_);
    const double w =
        (predicted + beta_ * (playedForce_ + linearForce_ - linearSlope_ * linearAt_)) / (1.0 - beta_ * linearSlope_);
    auto residualOf = [&](double x, double force, double dForce) {
        const double affine = linear ? linearForce_ + linearSlope_ * (x - linearAt_) : 0.0;
        return Residual{x - predicted - beta_ * (force + affine),
                        1.0 - beta_ * (dForce + (linear ? linearSlope_ : 0.0))};
    };
    double part = 0.0;
    const double bridge =
        secantOnStrings(strings, linearFrom_, split_, before, w, residualOf, tolerance, slope_, playedForce_, part);
    if (linearFrom_ > split_)
        partForce_ = part;
    playedForce_ += part;
    return bridge;
}

// A string's node at n+1, w = w^{n-1} + (2 dt / R) (a + F_s(w)), a the wave arriving: the secant on
// the string's trial where it has one, else its solve (secantOnStrings), as solveBridge for one
// string. Returns F_s there; the string keeps that solve.
double SharedBody::solveNode(ModalSolver& string, double before, double arriving, double& node)
{
    const double k = 2.0 * dt_ / linkImpedance_;
    auto tolerance = [&](double w) { return 1e-14 * (std::abs(w) + std::abs(k * arriving)) + 1e-30; };
    auto residualOf = [&](double x, double force, double dForce) {
        return Residual{x - before - k * (arriving + force), 1.0 - k * dForce};
    };
    ModalSolver* strings[1] = {&string};
    double slope = 1.0, force = 0.0, part = 0.0;
    node = secantOnStrings(strings, 1, 1, before, before + k * arriving, residualOf, tolerance, slope, force, part);
    return force;
}

bool SharedBody::bankLinear(ModalSolver* const* strings, int from, int to)
{
    if (banked_ || oneWay_ || linkImpedance_ > 0.0 || from >= to || !bank_.take(strings + from, to - from))
        return false;
    banked_ = true;
    bankFrom_ = from;  // the reach takes the others only from now (BodyReach sees the shorter list)
    return true;
}

void SharedBody::unbankLinear(ModalSolver* const* strings)
{
    if (!banked_)
        return;
    bank_.giveBack(strings + bankFrom_);
    banked_ = false;
}

void SharedBody::keepPart(bool keep)
{
    if (keep == partKept_)
        return;
    partKept_ = keep;
    if (keep)
        return;
    std::fill(zPart_.begin(), zPart_.end(), 0.0);
    std::fill(zPartPrevious_.begin(), zPartPrevious_.end(), 0.0);
    partPressure_.fill(0.0);
}

// The copy of the modes that the strings after split drive: the same update, their force alone.
void SharedBody::stepPart(double partForce)
{
    const int K = static_cast<int>(zPart_.size());
    const double* readings[2] = {heard_[0].data(), heard_[1].data()};
    double moved[2] = {};  // sum_k g_k (z~_k - z_k^{n-1}) per channel
    if (channels_ == 1)
        kernels::predictWith<1, 0>(a_.data(), e_.data(), zPart_.data(), zPartPrevious_.data(), readings, K, K, moved);
    else
        kernels::predictWith<2, 0>(a_.data(), e_.data(), zPart_.data(), zPartPrevious_.data(), readings, K, K, moved);
    kernels::axpy(partForce, push_.data(), zPartPrevious_.data(), K);
    std::swap(zPart_, zPartPrevious_);
    pressuresFrom(moved, partForce, partPressure_);
}

// The channels' pressures at t^n from their readings of z~ - z^{n-1} (`moved`: one value when both
// channels hear the same) and the step's force on the modes read.
void SharedBody::pressuresFrom(const double* moved, double force, std::array<double, 2>& out) const
{
    for (int c = 0; c < 2; ++c)
        out[size_t(c)] = (moved[channels_ == 1 ? 0 : c] + heardPush_[size_t(c)] * force) / (2.0 * dt_);
}

void SharedBody::listenAt(int listener)
{
    listener = std::clamp(listener, 0, listeners_ - 1);
    for (auto& channel : heard_)
        std::copy(weights_[size_t(listener)].begin(), weights_[size_t(listener)].end(), channel.begin());
    channels_ = 1;
    heardListener_ = listener;
    width_ = 0.0;
    pushHeard();
}

void SharedBody::listenBetween(double width)
{
    width = std::clamp(std::isfinite(width) ? width : 0.0, 0.0, 1.0);
    if (listeners_ < 3 || width == 0.0)
    {
        if (channels_ != 1 || heardListener_ != 0)
            listenAt(0);
        return;
    }
    if (width == width_ && channels_ == 2)
        return;
    const double u = 1.0 - width;
    for (size_t k = 0; k < heard_[0].size(); ++k)
        for (size_t c = 0; c < 2; ++c)
        {
            // (u c_0 + w c_s)^2 over the modes near k, against c^2: u^2 + w^2 + 2 u w rho_k. Divided
            // out, the power there stays what each listener hears.
            const double rho = sideCorrelation_[c][k];
            heard_[c][k] = (u * weights_[0][k] + width * weights_[1 + c][k])
                           / std::sqrt(u * u + width * width + 2.0 * u * width * rho);
        }
    channels_ = 2;
    width_ = width;
    pushHeard();
}

// sum_k g_k dt^2 kappa / m_k per channel: what the step's force adds to each channel's reading.
void SharedBody::pushHeard()
{
    const int K = static_cast<int>(push_.size());
    for (int c = 0; c < 2; ++c)
        heardPush_[size_t(c)] = kernels::dot(heard_[size_t(c)].data(), push_.data(), K);
}

void SharedBody::step(ModalSolver* const* strings, int count, int split)
{
    // z~ over z^{n-1}, with its bridge reading and the channels' readings of its change, in one pass.
    const int K = static_cast<int>(z_.size());
    const double* readings[3] = {kappa_.data(), heard_[0].data(), heard_[1].data()};
    double read[3] = {};
    if (channels_ == 1)
        kernels::predictWith<2, 1>(a_.data(), e_.data(), z_.data(), zPrevious_.data(), readings, K, K, read);
    else
        kernels::predictWith<3, 1>(a_.data(), e_.data(), z_.data(), zPrevious_.data(), readings, K, K, read);
    const double predicted = read[0];
    if (linkImpedance_ > 0.0)
    {
        stepLinked(strings, count, predicted);
        finishBody(predicted, read);
        return;
    }
    const int own = banked_ ? bankFrom_ : count;  // the strings stepped by their own solvers
    reach_.choose(strings, own, oneWay_, bridge_, bridgeBefore_);
    for (int i = 0; i < own; ++i)
        strings[i]->predictOnMovingBridge();
    if (banked_)
        bank_.predict();
    evaluations_ = trials_ = 0;
    split_ = split;
    count_ = count;
    linearFrom_ = split;
    for (int i = split; i < own && linearFrom_ < count; ++i)
        if (!standsOnSprings(*strings[i]))
            linearFrom_ = count;  // one of them can leave a point: each is solved at every evaluation
    if (linearFrom_ == count)
        linearForce_ = linearSlope_ = linearAt_ = 0.0;  // no affine part: none in the first W
    // One way, the strings' bridge stands still: their solve once, with it at rest.
    const double before = oneWay_ ? 0.0 : bridgeBefore_;
    double bridge = oneWay_ ? 0.0 : solveBridge(strings, before, predicted);
    resolved_ =
        !oneWay_
        && !reach_.withinBudgets(forces_.data(), std::min(linearFrom_, BodyReach::kMostStrings), before, bridge);
    if (resolved_)
    {
        // Beyond what the live points were chosen for: the step again with every point.
        for (int i = 0; i < linearFrom_; ++i)
            strings[i]->wakeAllMidStep();
        reach_.chooseAgain();
        bridge = solveBridge(strings, before, predicted);
    }
    if (oneWay_)
    {
        evaluate(strings, 0.0, 0.0);
        evaluations_ = 1;
    }
    force_ = playedForce_;  // with the strings after split when they are not linear
    if (linearFrom_ < count)
    {
        partForce_ = banked_ ? bank_.solve(before, bridge - before) : solveForce(strings, split, count, before, bridge);
        force_ += partForce_;
    }
    for (int i = 0; i < own; ++i)
        strings[i]->finishOnMovingBridge();
    if (banked_)
        bank_.finish();
    if (split < count && partKept_)
        stepPart(partForce_);
    finishBody(predicted, read);
}

// The body's step with the step's force_: z^{n+1} = z~ + (dt^2 kappa / m_k) F, its bridge and the
// channels' pressures.
void SharedBody::finishBody(double predicted, const double* read)
{
    const int K = static_cast<int>(z_.size());
    kernels::axpy(force_, push_.data(), zPrevious_.data(), K);
    std::swap(z_, zPrevious_);
    bridgeBefore_ = bridge_;
    bridge_ = predicted + beta_ * force_;
    pressuresFrom(read + 1, force_, pressure_);
}

}  // namespace jawari
