#include "ModalSolver.h"

#include "FftwPlanner.h"
#include "ModalKernels.h"

#include <fftw3.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <string>
#include <utility>

namespace jawari
{
namespace
{
// Grid node of each contact point on the reference grid x_i = i L/(M+1), or an empty vector when
// some point is off the grid or two points share a node (then only projection applies).
std::vector<int> distinctGridNodes(const std::vector<ContactPoint>& contacts, double L, int M)
{
    const int N = M + 1;
    const double dx = L / N;
    std::vector<int> nodes;
    std::vector<char> used(N + 1, 0);
    for (const auto& c : contacts)
    {
        const double node = std::round(c.position / dx);
        if (std::abs(c.position / dx - node) > 1e-9 || node < 1 || node > N - 1 || used[int(node)])
            return {};
        used[int(node)] = 1;
        nodes.push_back(int(node));
    }
    return nodes;
}
}  // namespace

struct ModalSolver::Transform
{
    explicit Transform(int n)
        : size(n)
    {
        in = fftw_alloc_real(n);
        out = fftw_alloc_real(n);
        energyIn = fftw_alloc_real(n);
        energyOut = fftw_alloc_real(n);
        std::lock_guard<std::mutex> lock(fftwPlannerMutex());
        plan = fftw_plan_r2r_1d(n, in, out, FFTW_RODFT00, FFTW_MEASURE);
        if (plan == nullptr)
            throw std::runtime_error("FFTW could not plan a DST-I of size " + std::to_string(n));
    }
    ~Transform()
    {
        {
            std::lock_guard<std::mutex> lock(fftwPlannerMutex());
            fftw_destroy_plan(plan);
        }
        fftw_free(in);
        fftw_free(out);
        fftw_free(energyIn);
        fftw_free(energyOut);
    }
    Transform(const Transform&) = delete;
    Transform& operator=(const Transform&) = delete;

    int size;
    fftw_plan plan = nullptr;
    double* in = nullptr;
    double* out = nullptr;
    double* energyIn = nullptr;  // separate buffers so energy() leaves the stepping state alone
    double* energyOut = nullptr;
    std::vector<int> nodes;  // grid node of contact point j
    double scale = 0.0;      // sqrt(2/L)/2: S v = scale * RODFT00(v), S^T likewise
};

ModalSolver::ModalSolver(const ModalSolverConfig& config)
    : M_(config.modes.size())
    , P_(static_cast<int>(config.contacts.size()))
    , dt_(config.timeStep)
    , mu_(config.linearDensity)
    , forceScale_(config.timeStep * config.timeStep / config.linearDensity)
    , contacts_(config.contacts)
{
    if (M_ < 1)
        throw std::invalid_argument("the modal solver needs at least one mode");
    if (!(dt_ > 0.0) || !(mu_ > 0.0) || !(config.lengthMetres > 0.0))
        throw std::invalid_argument("the modal solver needs a positive time step, density and length");
    const double L = config.lengthMetres;

    coeffs_.resize(M_);
    coeffsReleased_.resize(M_);
    omega_ = config.modes.omega;
    sigma_ = config.modes.sigma;
    releaseSigma_ = config.releaseSigma;
    for (int p = 0; p < M_; ++p)
    {
        coeffs_[p] = exactCoefficients(omega_[p], sigma_[p], dt_);
        coeffsReleased_[p] = exactCoefficients(omega_[p], sigma_[p] + config.releaseSigma, dt_);
    }
    pickupWeights_ = config.pickupWeights;
    pickupWeights_.resize(M_, 0.0);
    basePickupWeights_ = pickupWeights_;
    for (auto* v : {&uC_, &uCPrev_, &uTilde_, &s_, &b_, &r_, &slope_, &pickupPhiW_})
        v->assign(P_, 0.0);

    const auto nodes = distinctGridNodes(contacts_, L, M_);
    const bool gridAllows = P_ > 0 && !nodes.empty();
    bool useTransform = false;
    switch (config.path)
    {
        case ContactPath::transform:
            if (!gridAllows)
                throw std::invalid_argument(
                    "the transform path needs every contact point on a distinct node of the grid x_i = i L/(M+1)");
            useTransform = true;
            break;
        case ContactPath::projection: useTransform = false; break;
        case ContactPath::automatic: useTransform = gridAllows && P_ > 24; break;
    }

    shapes_.resize(static_cast<size_t>(P_) * M_);
    for (int j = 0; j < P_; ++j)
        for (int p = 0; p < M_; ++p)
            shapes_[size_t(j) * M_ + p] = modeShape(L, p + 1, contacts_[j].position);
    for (int j = 0; j < P_; ++j)
    {
        double hp = 0.0;
        for (int p = 0; p < M_; ++p)
            hp += pickupWeights_[p] * shapes_[size_t(j) * M_ + p];
        pickupPhiW_[j] = forceScale_ * contacts_[j].weight * hp;
    }
    // A mode is coupled when some contact point, or the excitation point, sees it above rounding
    // (|phi| <= sqrt(2/L)).
    coupled_.assign(M_, useTransform || config.keepEveryMode ? 1 : 0);
    const double couplingFloor = 1e-13 * std::sqrt(2.0 / L);
    for (int j = 0; j < P_; ++j)
        for (int p = 0; p < M_; ++p)
            if (std::abs(shapes_[size_t(j) * M_ + p]) > couplingFloor)
                coupled_[p] = 1;
    if (config.excitationPosition)
    {
        excitationShape_.resize(M_);
        for (int p = 0; p < M_; ++p)
        {
            excitationShape_[p] = modeShape(L, p + 1, *config.excitationPosition);
            if (std::abs(excitationShape_[p]) > couplingFloor)
                coupled_[p] = 1;
        }
        pickupPhiE_ = forceScale_ * kernels::dot(pickupWeights_.data(), excitationShape_.data(), M_);
    }

    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(P_, P_);
    if (useTransform)
    {
        transform_ = std::make_unique<Transform>(M_);
        transform_->nodes = nodes;
        transform_->scale = 0.5 * std::sqrt(2.0 / L);
        const double dx = L / (M_ + 1);
        // On the grid with M = N - 1, S dx S^T = I: Phi Phi^T W = diag(w_j / dx).
        for (int j = 0; j < P_; ++j)
            A(j, j) = forceScale_ * contacts_[j].weight / dx;
        shapes_.clear();
        shapes_.shrink_to_fit();
    }
    else
    {
        for (int i = 0; i < P_; ++i)
            for (int j = 0; j < P_; ++j)
                A(i, j) = forceScale_ * contacts_[j].weight
                          * kernels::dot(&shapes_[size_t(i) * M_], &shapes_[size_t(j) * M_], M_);
    }
    stringCoupling_ = A;
    delta_.assign(P_, 0.0);
    deltaPrev_.assign(P_, 0.0);
    if (!config.contactCompliance.empty() && !useTransform)
    {
        if (config.contactCompliance.size() != size_t(P_) * P_)
            throw std::invalid_argument("contact compliance must be P x P");
        Eigen::MatrixXd C = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
            config.contactCompliance.data(), P_, P_);
        baseComplianceC_ = C;
        complianceW_ = C;
        for (int j = 0; j < P_; ++j)
            complianceW_.col(j) *= contacts_[j].weight;
        complianceInverse_ = C.inverse();
        baseComplianceInverse_ = complianceInverse_;
        couplingScratch_ = A + complianceW_;
        // The contact sees the true displacement change R = r + delta^{n+1} - delta^{n-1}
        //   = (b - delta^{n-1}) + (A + C W) f: the same equation with A + C W.
        A += complianceW_;
    }
    method_ = config.method;
    pointCoupling_ = A;
    for (int j = 0; j < P_; ++j)
        pointCoupling_.col(j) /= contacts_[j].weight;
    savGradient_.assign(P_, 0.0);
    savResponse_.assign(P_, 0.0);
    system_.prepare(contacts_, std::move(A));
    setState(std::vector<double>(M_, 0.0), std::vector<double>(M_, 0.0));
}

ModalSolver::~ModalSolver() = default;

void ModalSolver::compact(const std::vector<double>& current, const std::vector<double>& previous)
{
    double largest = 0.0;
    for (int p = 0; p < M_; ++p)
        largest = std::max({largest, std::abs(current[p]), std::abs(previous[p])});
    const double stateFloor = 1e-13 * largest;
    active_.clear();
    for (int p = 0; p < M_; ++p)
        if (coupled_[p] || std::abs(current[p]) > stateFloor || std::abs(previous[p]) > stateFloor)
            active_.push_back(p);
    Ma_ = static_cast<int>(active_.size());
    // Padding to whole blocks keeps the kernels off their scalar tail loops (a = e = h = phi = 0).
    Mpad_ = (Ma_ + kernels::kBlock - 1) / kernels::kBlock * kernels::kBlock;
    if (transform_)
        Mpad_ = Ma_;  // the DST works on exactly M values
    activeCoeffs_.resize(Ma_);
    activeCoeffsReleased_.resize(Ma_);
    indexOfMode_.assign(M_, -1);
    // stride_ * 8 bytes = 576 (mod 4096): consecutive arrays sit 9 cache lines apart modulo 4 KiB.
    stride_ = (Mpad_ + 7) / 8 * 8;
    while ((stride_ * 8) % 4096 != 576)
        stride_ += 8;
    const int arrays = 9 + (transform_ ? 0 : P_);
    storage_.assign(static_cast<size_t>(stride_) * arrays + 8, 0.0);
    double* base = storage_.data();
    while (reinterpret_cast<std::uintptr_t>(base) % 64 != 0)
        ++base;
    double* next = base;
    for (double** array : {&aNormal_, &eNormal_, &aReleased_, &eReleased_, &h_, &q_, &qPrev_, &settled_, &phiE_})
    {
        *array = next;
        next += stride_;
    }
    phi_ = transform_ ? nullptr : next;
    for (int i = 0; i < Ma_; ++i)
    {
        const int p = active_[i];
        indexOfMode_[p] = i;
        q_[i] = current[p];
        qPrev_[i] = previous[p];
        phiE_[i] = excitationShape_.empty() ? 0.0 : excitationShape_[p];
    }
    released_ = false;
    a_ = aNormal_;
    e_ = eNormal_;
    if (!transform_)
    {
        for (int j = 0; j < P_; ++j)
            for (int i = 0; i < Ma_; ++i)
                phi_[size_t(j) * stride_ + i] = shapes_[size_t(j) * M_ + active_[i]];
    }
    canPair_ = !transform_ && P_ <= 1;
    layout_ = Layout::single;
    c1_ = c2_ = 0.0;
    fillActiveTables();
}

void ModalSolver::fillActiveTables()
{
    for (int i = 0; i < Ma_; ++i)
    {
        const int p = active_[i];
        activeCoeffs_[i] = coeffs_[p];
        activeCoeffsReleased_[i] = coeffsReleased_[p];
        aNormal_[i] = coeffs_[p].a;
        eNormal_[i] = coeffs_[p].e;
        aReleased_[i] = coeffsReleased_[p].a;
        eReleased_[i] = coeffsReleased_[p].e;
        h_[i] = pickupWeights_[p];
    }
    for (int set = 0; set < 2; ++set)
    {
        const double* a = set == 0 ? aNormal_ : aReleased_;
        sumAPhiSquared_[set] = sumAPhiH_[set] = 0.0;
        if (canPair_ && P_ == 1)
            for (int i = 0; i < Ma_; ++i)
            {
                sumAPhiSquared_[set] += a[i] * phi_[i] * phi_[i];
                sumAPhiH_[set] += a[i] * phi_[i] * h_[i];
            }
    }
}

void ModalSolver::setState(const std::vector<double>& current, const std::vector<double>& previous)
{
    if (static_cast<int>(current.size()) != M_ || static_cast<int>(previous.size()) != M_)
        throw std::invalid_argument("modal state has the wrong number of modes");
    compact(current, previous);
    restartFromModes();
}

void ModalSolver::restartFromModes()
{
    // Everything derived from the modal state, afresh: contact displacements, pickup, the
    // compliance deflections and the quadratised variable (xi = sqrt(2 V) at n and n-1).
    system_.reset();
    std::fill(delta_.begin(), delta_.end(), 0.0);
    std::fill(deltaPrev_.begin(), deltaPrev_.end(), 0.0);
    projectActive(q_, uC_.data());
    projectActive(qPrev_, uCPrev_.data());
    pickup_ = kernels::dot(h_, q_, Ma_);
    xi_ = xiPrev_ = 0.0;
    for (int j = 0; j < P_; ++j)
    {
        xi_ += contacts_[j].weight * contactPotential(contacts_[j].law, contacts_[j].height - uC_[j]);
        xiPrev_ += contacts_[j].weight * contactPotential(contacts_[j].law, contacts_[j].height - uCPrev_[j]);
    }
    xi_ = std::sqrt(2.0 * xi_);
    xiPrev_ = std::sqrt(2.0 * xiPrev_);
}

void ModalSolver::setInitialDisplacement(const std::vector<double>& modalDisplacement)
{
    if (static_cast<int>(modalDisplacement.size()) != M_)
        throw std::invalid_argument("initial displacement has the wrong number of modes");
    // q^{-1} is the exact free motion one step back, so a run without contact is the analytic
    // solution. For a mode damped by more than e^0.5 per step that value is huge (e^{sigma dt}: the
    // top modes of a fine grid at an audio rate reach e^26) and the recurrence would cancel huge
    // numbers; such a mode starts at rest in the centred sense instead, q^{-1} = q(+dt).
    std::vector<double> previous(M_, 0.0);
    for (int p = 0; p < M_; ++p)
    {
        previous[p] = previousAtRest(p, modalDisplacement[p]);
    }
    setState(modalDisplacement, previous);
}

void ModalSolver::step()
{
    if (canPair_ && externalForce_ == 0.0)
    {
        if (layout_ == Layout::single)
        {
            layout_ = Layout::pairBoundary;  // q_ = q^n, qPrev_ = q^{n-1}: the boundary form with c = 0
            c1_ = c2_ = 0.0;
        }
        stepPaired();
        return;
    }
    toSingle();
    stepSingle();
}

void ModalSolver::toSingle()
{
    if (layout_ == Layout::single)
        return;
    const double* phi = P_ == 1 ? phi_ : nullptr;
    if (layout_ == Layout::pairBoundary)
    {
        if (phi != nullptr)
            for (int i = 0; i < Mpad_; ++i)
            {
                q_[i] += (c1_ * a_[i] + c2_) * phi[i];
                qPrev_[i] += c1_ * phi[i];
            }
    }
    else
        for (int i = 0; i < Mpad_; ++i)
        {
            q_[i] = qPrev_[i] + (phi != nullptr ? c1_ * phi[i] : 0.0);
            qPrev_[i] = settled_[i];
        }
    c1_ = c2_ = 0.0;
    layout_ = Layout::single;
}

void ModalSolver::setExternalForce(double newtons)
{
    externalForce_ = excitationShape_.empty() ? 0.0 : newtons;
}

void ModalSolver::setReleased(bool released)
{
    if (released == released_)
        return;
    toSingle();  // the paired layout's corrections use the coefficients of its pass
    released_ = released;
    a_ = released ? aReleased_ : aNormal_;
    e_ = released ? eReleased_ : eNormal_;
}

double ModalSolver::stringEnergy() const
{
    const auto& coefficients = released_ ? activeCoeffsReleased_ : activeCoeffs_;
    const double* phi = P_ == 1 ? phi_ : nullptr;
    double sum = 0.0;
    for (int i = 0; i < Ma_; ++i)
    {
        const double ph = phi != nullptr ? phi[i] : 0.0;
        double now = q_[i], before = qPrev_[i];
        if (layout_ == Layout::pairMiddle)
        {
            now = qPrev_[i] + c1_ * ph;
            before = settled_[i];
        }
        else if (layout_ == Layout::pairBoundary)
        {
            now = q_[i] + (c1_ * a_[i] + c2_) * ph;
            before = qPrev_[i] + c1_ * ph;
        }
        const double v = (now - before) / dt_;
        sum += coefficients[i].kineticWeight * v * v + coefficients[i].potentialWeight * now * before;
    }
    return 0.5 * mu_ * sum;
}

double ModalSolver::pickupCompliance() const
{
    double sum = 0.0;
    for (int p = 0; p < M_; ++p)
        sum += pickupWeights_[p] * pickupWeights_[p] / (mu_ * omega_[p] * omega_[p]);
    return sum;
}

void ModalSolver::retune(const double* omega, const double* sigma, double complianceScale, double pickupScale)
{
    toSingle();  // the paired layout's corrections were made with the old coefficients
    for (int p = 0; p < M_; ++p)
    {
        omega_[p] = omega[p];
        sigma_[p] = sigma[p];
        coeffs_[p] = exactCoefficients(omega_[p], sigma_[p], dt_);
        coeffsReleased_[p] = exactCoefficients(omega_[p], sigma_[p] + releaseSigma_, dt_);
        pickupWeights_[p] = pickupScale * basePickupWeights_[p];
    }
    fillActiveTables();
    for (int j = 0; j < P_ && !transform_; ++j)
        pickupPhiW_[j] = forceScale_ * contacts_[j].weight * kernels::dot(h_, phi_ + size_t(j) * stride_, Ma_);
    if (!excitationShape_.empty())
        pickupPhiE_ = forceScale_ * kernels::dot(h_, phiE_, Ma_);
    pickup_ = kernels::dot(h_, q_, Ma_);
    if (complianceW_.size() != 0)
    {
        for (int i = 0; i < P_; ++i)
            for (int j = 0; j < P_; ++j)
            {
                complianceW_(i, j) = complianceScale * baseComplianceC_(i, j) * contacts_[j].weight;
                complianceInverse_(i, j) = baseComplianceInverse_(i, j) / complianceScale;  // no Eigen inverse here
            }
        for (int i = 0; i < P_; ++i)
            for (int j = 0; j < P_; ++j)
            {
                const double a = stringCoupling_(i, j) + complianceW_(i, j);
                pointCoupling_(i, j) = a / contacts_[j].weight;
                couplingScratch_(i, j) = a;
            }
        system_.setCoupling(couplingScratch_);
    }
}

double ModalSolver::previousAtRest(int p, double q0) const
{
    const double back = sigma_[p] * dt_ <= 0.5 ? -dt_ : dt_;  // see setInitialDisplacement()
    return freeDampedMotion(q0, 0.0, omega_[p], sigma_[p], back);
}

void ModalSolver::startFrom(const double* modalDisplacement)
{
    layout_ = Layout::single;
    c1_ = c2_ = 0.0;
    for (int i = 0; i < Ma_; ++i)
    {
        const int p = active_[i];
        q_[i] = modalDisplacement[p];
        qPrev_[i] = previousAtRest(p, modalDisplacement[p]);
    }
    restartFromModes();
}

void ModalSolver::setContact(int j, const ContactLaw& law, double height)
{
    contacts_[size_t(j)].law = law;
    contacts_[size_t(j)].height = height;
    system_.setLaw(j, law);
}

void ModalSolver::displacementAt(const double* shapes, int count, double* out)
{
    toSingle();
    for (int k = 0; k < count; ++k)
    {
        double u = 0.0;
        for (int i = 0; i < Ma_; ++i)
            u += q_[i] * shapes[size_t(k) * M_ + active_[i]];
        out[k] = u;
    }
}

void ModalSolver::resetToRest()
{
    std::fill(q_, q_ + Mpad_, 0.0);
    std::fill(qPrev_, qPrev_ + Mpad_, 0.0);
    std::fill(settled_, settled_ + Mpad_, 0.0);
    layout_ = Layout::single;
    c1_ = c2_ = 0.0;
    externalForce_ = 0.0;
    system_.reset();
    for (auto* v : {&uC_, &uCPrev_, &delta_, &deltaPrev_})
        std::fill(v->begin(), v->end(), 0.0);
    xi_ = xiPrev_ = 0.0;
    pickup_ = pickupTilde_ = 0.0;
}

void ModalSolver::copyStateFrom(ModalSolver& other)
{
    other.toSingle();
    toSingle();
    for (int i = 0; i < Ma_; ++i)
    {
        const int p = active_[i];
        const int k = p < other.M_ ? other.indexOfMode_[p] : -1;
        q_[i] = k >= 0 ? other.q_[k] : 0.0;
        qPrev_[i] = k >= 0 ? other.qPrev_[k] : 0.0;
    }
    restartFromModes();
}

double ModalSolver::solveOnePoint(double uTilde)
{
    s_[0] = contacts_[0].height - uCPrev_[0] - deltaPrev_[0];
    b_[0] = uTilde - uCPrev_[0] - deltaPrev_[0];
    lastIterations_ = solveContacts();
    // u_C^{n+1} = u~ + A f with f = -G.
    uCPrev_[0] = uC_[0];
    uC_[0] = uTilde - stringCoupling_(0, 0) * slope_[0];
    advanceCompliance();
    lastPenetration_ = contacts_[0].height - uC_[0] - delta_[0];
    return slope_[0];
}

int ModalSolver::solveContacts()
{
    switch (method_)
    {
        case ContactMethod::energyConserving: return system_.solve(s_.data(), b_.data(), r_.data(), slope_.data());
        case ContactMethod::penalty:
            // f^n = K [g - u^n]_+^alpha, explicit.
            for (int j = 0; j < P_; ++j)
            {
                const double penetration = contacts_[j].height - uC_[j] - delta_[j];
                slope_[j] = penetration > 0.0
                                ? -contacts_[j].law.stiffness * std::pow(penetration, contacts_[j].law.exponent)
                                : 0.0;
            }
            return 0;
        case ContactMethod::quadratised: return solveQuadratised();
    }
    return 0;
}

int ModalSolver::solveQuadratised()
{
    // Energy quadratisation (Ducceschi & Bilbao 2019): V(u) = sum_j w_j psi_j(u_j) = xi^2 / 2 with
    // xi carried as a state. With g = dV/du / sqrt(2 V) at u^n, the point forces are
    //   F = -g (xi^{n+1} + xi^{n-1}) / 2,   xi^{n+1} = xi^{n-1} + g . R,
    // and R = b + B F (B = A' W^{-1}), so (I + B g g^T / 2) R = b - B g xi^{n-1}: one rank-one
    // solve (Sherman-Morrison), no iteration. The quadratised energy is conserved exactly.
    double V = 0.0;
    bool touching = false;
    for (int j = 0; j < P_; ++j)
    {
        const double penetration = contacts_[j].height - uC_[j] - delta_[j];
        const auto& law = contacts_[j].law;
        if (penetration > 0.0)
        {
            touching = true;
            V += contacts_[j].weight * contactPotential(law, penetration);
            savGradient_[j] = -contacts_[j].weight * law.stiffness * std::pow(penetration, law.exponent);
        }
        else
            savGradient_[j] = 0.0;
    }
    if (!touching || V <= 0.0)
    {
        // Out of contact V = 0, so xi = sqrt(2 V) = 0: what the recursion xi^{n+1} = xi^{n-1}
        // would carry over is drift, released here (it can only lower the energy) instead of
        // pushing with a stale force at the next contact.
        std::fill(slope_.begin(), slope_.end(), 0.0);
        xiPrev_ = xi_;
        xi_ = 0.0;
        return 0;
    }
    const double root = std::sqrt(2.0 * V);
    double gDotB = 0.0, gDotV = 0.0;
    for (int j = 0; j < P_; ++j)
        savGradient_[j] /= root;
    for (int i = 0; i < P_; ++i)
    {
        double v = 0.0;
        for (int j = 0; j < P_; ++j)
            v += pointCoupling_(i, j) * savGradient_[j];
        savResponse_[i] = v;  // B g
    }
    for (int j = 0; j < P_; ++j)
    {
        gDotB += savGradient_[j] * (b_[j] - savResponse_[j] * xiPrev_);
        gDotV += savGradient_[j] * savResponse_[j];
    }
    const double gDotR = gDotB / (1.0 + 0.5 * gDotV);  // g . R from Sherman-Morrison
    const double mean = xiPrev_ + 0.5 * gDotR;         // (xi^{n+1} + xi^{n-1}) / 2
    for (int j = 0; j < P_; ++j)
        slope_[j] = savGradient_[j] * mean / contacts_[j].weight;  // f = F / w = -g mean / w; G = -f
    const double xiNext = xiPrev_ + gDotR;
    xiPrev_ = xi_;
    xi_ = xiNext;
    return 0;
}

void ModalSolver::advanceCompliance()
{
    if (complianceW_.size() == 0)
        return;
    // An element loop, not std::copy/fill: P is mostly 1, where their calls cost more than the work.
    for (int j = 0; j < P_; ++j)
    {
        deltaPrev_[j] = delta_[j];
        delta_[j] = 0.0;
    }
    // delta = -C W G, column by column over the points that press (most do not, most of the time).
    for (int i = 0; i < P_; ++i)
        if (slope_[i] != 0.0)
        {
            const double* column = complianceW_.data() + static_cast<ptrdiff_t>(i) * P_;  // column-major
            const double g = slope_[i];
            for (int j = 0; j < P_; ++j)
                delta_[j] -= column[j] * g;
        }
}

void ModalSolver::stepPaired()
{
    lastIterations_ = 0;
    lastPenetration_ = -std::numeric_limits<double>::infinity();
    const double* phi = P_ == 1 ? phi_ : nullptr;
    if (layout_ == Layout::pairBoundary)
    {
        double u1 = 0.0;
        kernels::pairStep(a_, e_, qPrev_, q_, settled_, h_, phi, c1_, c2_, Mpad_, pickupTilde_, u1, pairPickup2_,
                          pairContact2_);
        double y = pickupTilde_;
        c1_ = c2_ = 0.0;
        if (P_ == 1)
        {
            const double G = solveOnePoint(u1);
            c1_ = -forceScale_ * contacts_[0].weight * G;  // q^{n+1} = q~ + c1 phi
            y -= pickupPhiW_[0] * G;
        }
        pickup_ = y;
        layout_ = Layout::pairMiddle;
        return;
    }
    // Second step of the pair: q~^{n+2} = Y + c1 a phi, so its projections gain c1 sum(a phi phi).
    const int set = released_ ? 1 : 0;
    double y = pairPickup2_ + c1_ * sumAPhiH_[set];
    if (P_ == 1)
    {
        const double G = solveOnePoint(pairContact2_ + c1_ * sumAPhiSquared_[set]);
        c2_ = -forceScale_ * contacts_[0].weight * G;
        y -= pickupPhiW_[0] * G;
    }
    pickup_ = y;
    layout_ = Layout::pairBoundary;
}

void ModalSolver::stepSingle()
{
    // q~ = a q - e q^{n-1}, written over q^{n-1}; its pickup and contact projections.
    const bool fused = !transform_ && externalForce_ == 0.0 && P_ > 0 && P_ <= kernels::kMaxFused;
    if (fused)
        pickupTilde_ = kernels::predictProject(a_, e_, q_, qPrev_, h_, phi_, stride_, P_, Mpad_, uTilde_.data());
    else
        pickupTilde_ = kernels::predict(a_, e_, q_, qPrev_, h_, Mpad_);
    if (externalForce_ != 0.0)
    {
        // The explicit point force joins the prediction: q~ += (dt^2/mu) F phi_e.
        kernels::axpy(forceScale_ * externalForce_, phiE_, qPrev_, Mpad_);
        pickupTilde_ += externalForce_ * pickupPhiE_;
    }
    if (transform_)
    {
        double* in = transform_->in;
        std::copy(qPrev_, qPrev_ + M_, in);
        fftw_execute(transform_->plan);
        for (int j = 0; j < P_; ++j)
            uTilde_[j] = transform_->scale * transform_->out[transform_->nodes[j] - 1];
    }
    else if (!fused)
        for (int j = 0; j < P_; ++j)
            uTilde_[j] = kernels::dot(phi_ + size_t(j) * stride_, qPrev_, Mpad_);

    bool anyForce = false;
    lastIterations_ = 0;
    if (P_ > 0)
    {
        for (int j = 0; j < P_; ++j)
        {
            s_[j] = contacts_[j].height - uCPrev_[j] - deltaPrev_[j];
            b_[j] = uTilde_[j] - uCPrev_[j] - deltaPrev_[j];
        }
        lastIterations_ = solveContacts();
        for (int j = 0; j < P_; ++j)
            anyForce = anyForce || slope_[j] != 0.0;
    }

    double y = pickupTilde_;
    if (anyForce)
    {
        // q^{n+1} = q~ + (dt^2/mu) Phi^T W f with f = -G(r).
        double* next = qPrev_;
        if (transform_)
        {
            double* in = transform_->in;
            std::fill(in, in + M_, 0.0);
            for (int j = 0; j < P_; ++j)
                in[transform_->nodes[j] - 1] = -contacts_[j].weight * slope_[j];
            fftw_execute(transform_->plan);
            kernels::axpy(forceScale_ * transform_->scale, transform_->out, next, M_);
        }
        else
            for (int j = 0; j < P_; ++j)
                if (slope_[j] != 0.0)
                    kernels::axpy(-forceScale_ * contacts_[j].weight * slope_[j], phi_ + size_t(j) * stride_, next,
                                  Mpad_);
        const auto& A = stringCoupling_;
        for (int j = 0; j < P_; ++j)
        {
            double Af = 0.0;
            for (int i = 0; i < P_; ++i)
                Af -= A(j, i) * slope_[i];
            uTilde_[j] += Af;  // u_C^{n+1} = u~ + A f
            y -= pickupPhiW_[j] * slope_[j];
        }
    }

    if (P_ > 0)
        advanceCompliance();
    lastPenetration_ = -std::numeric_limits<double>::infinity();
    for (int j = 0; j < P_; ++j)
    {
        uCPrev_[j] = uC_[j];
        uC_[j] = uTilde_[j];
        lastPenetration_ = std::max(lastPenetration_, contacts_[j].height - uC_[j] - delta_[j]);
    }
    std::swap(q_, qPrev_);
    pickup_ = y;
}

void ModalSolver::fullState(std::vector<double>& current, std::vector<double>& previous) const
{
    // Active-mode state (q^n, q^{n-1}) as stored, with the paired path's corrections applied.
    current.resize(Ma_);
    previous.resize(Ma_);
    const double* phi = P_ == 1 ? phi_ : nullptr;
    for (int i = 0; i < Ma_; ++i)
    {
        const double ph = phi != nullptr ? phi[i] : 0.0;
        if (layout_ == Layout::single)
        {
            current[i] = q_[i];
            previous[i] = qPrev_[i];
        }
        else if (layout_ == Layout::pairMiddle)
        {
            current[i] = qPrev_[i] + c1_ * ph;
            previous[i] = settled_[i];
        }
        else
        {
            current[i] = q_[i] + (c1_ * a_[i] + c2_) * ph;
            previous[i] = qPrev_[i] + c1_ * ph;
        }
    }
}

std::vector<double> ModalSolver::modalState(bool previous)
{
    std::vector<double> current, before;
    fullState(current, before);
    std::vector<double> full(M_, 0.0);
    const auto& src = previous ? before : current;
    for (int i = 0; i < Ma_; ++i)
        full[active_[i]] = src[i];
    return full;
}

void ModalSolver::projectActive(const double* qActive, double* u) const
{
    if (P_ == 0)
        return;
    if (transform_)
    {
        std::copy(qActive, qActive + M_, transform_->energyIn);
        fftw_execute_r2r(transform_->plan, transform_->energyIn, transform_->energyOut);
        for (int j = 0; j < P_; ++j)
            u[j] = transform_->scale * transform_->energyOut[transform_->nodes[j] - 1];
        return;
    }
    for (int j = 0; j < P_; ++j)
        u[j] = kernels::dot(phi_ + size_t(j) * stride_, qActive, Ma_);
}

double ModalSolver::stepLoss(const double* next, const double* previous) const
{
    double sum = 0.0;
    for (int p = 0; p < M_; ++p)
    {
        const double v = (next[p] - previous[p]) / (2.0 * dt_);
        sum += coeffs_[p].lossWeight * v * v;
    }
    return mu_ * sum;
}

ModalSolver::Energy ModalSolver::energy()
{
    std::vector<double> current, previous;
    fullState(current, previous);
    Energy out;
    std::vector<double> u(P_), uPrev(P_);
    projectActive(current.data(), u.data());
    projectActive(previous.data(), uPrev.data());
    for (int j = 0; j < P_; ++j)
        out.contact += contacts_[j].weight * 0.5
                       * (contactPotential(contacts_[j].law, contacts_[j].height - u[j] - delta_[j])
                          + contactPotential(contacts_[j].law, contacts_[j].height - uPrev[j] - deltaPrev_[j]));
    if (method_ == ContactMethod::quadratised)
        out.contact = 0.25 * (xi_ * xi_ + xiPrev_ * xiPrev_);  // the quadratised contact energy, V = xi^2/2
    if (complianceW_.size() != 0)
    {
        // The dropped modes' static spring: (delta^T C^{-1} delta at n and n-1) / 2, averaged.
        const Eigen::Map<const Eigen::VectorXd> d(delta_.data(), P_), dPrev(deltaPrev_.data(), P_);
        out.contact += 0.25 * (d.dot(complianceInverse_ * d) + dPrev.dot(complianceInverse_ * dPrev));
    }
    out.total = stringEnergy() + out.contact;
    return out;
}

}  // namespace jawari
