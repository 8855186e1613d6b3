#include "ModalSolver.h"

#include "FftwPlanner.h"
#include "ModalKernels.h"

#include <fftw3.h>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <stdexcept>
#include <limits>
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
    explicit Transform(int n) : size(n)
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
    double* energyIn = nullptr;   // separate buffers so energy() leaves the stepping state alone
    double* energyOut = nullptr;
    std::vector<int> nodes;       // grid node of contact point j
    double scale = 0.0;           // sqrt(2/L)/2: S v = scale * RODFT00(v), S^T likewise
};

ModalSolver::ModalSolver(const ModalSolverConfig& config)
    : M_(config.modes.size()),
      P_(static_cast<int>(config.contacts.size())),
      dt_(config.timeStep),
      mu_(config.linearDensity),
      forceScale_(config.timeStep * config.timeStep / config.linearDensity),
      contacts_(config.contacts)
{
    if (M_ < 1)
        throw std::invalid_argument("the modal solver needs at least one mode");
    if (!(dt_ > 0.0) || !(mu_ > 0.0) || !(config.lengthMetres > 0.0))
        throw std::invalid_argument("the modal solver needs a positive time step, density and length");
    const double L = config.lengthMetres;

    coeffs_.resize(M_);
    omega_ = config.modes.omega;
    sigma_ = config.modes.sigma;
    for (int p = 0; p < M_; ++p)
        coeffs_[p] = exactCoefficients(omega_[p], sigma_[p], dt_);
    pickupWeights_ = config.pickupWeights;
    pickupWeights_.resize(M_, 0.0);
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
    // A mode is coupled when some contact point sees it above rounding (|phi| <= sqrt(2/L)).
    coupled_.assign(M_, useTransform ? 1 : 0);
    const double couplingFloor = 1e-13 * std::sqrt(2.0 / L);
    for (int j = 0; j < P_; ++j)
        for (int p = 0; p < M_; ++p)
            if (std::abs(shapes_[size_t(j) * M_ + p]) > couplingFloor)
                coupled_[p] = 1;

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
    activeCoeffs_.resize(Ma_);
    for (auto* v : {&a_, &e_, &h_, &q_, &qPrev_})
        v->resize(Ma_);
    for (int i = 0; i < Ma_; ++i)
    {
        const int p = active_[i];
        activeCoeffs_[i] = coeffs_[p];
        a_[i] = coeffs_[p].a;
        e_[i] = coeffs_[p].e;
        h_[i] = pickupWeights_[p];
        q_[i] = current[p];
        qPrev_[i] = previous[p];
    }
    if (!transform_)
    {
        phi_.resize(static_cast<size_t>(P_) * Ma_);
        for (int j = 0; j < P_; ++j)
            for (int i = 0; i < Ma_; ++i)
                phi_[size_t(j) * Ma_ + i] = shapes_[size_t(j) * M_ + active_[i]];
    }
}

void ModalSolver::setState(const std::vector<double>& current, const std::vector<double>& previous)
{
    if (static_cast<int>(current.size()) != M_ || static_cast<int>(previous.size()) != M_)
        throw std::invalid_argument("modal state has the wrong number of modes");
    compact(current, previous);
    pendingCorrection_ = 0.0;
    system_.reset();
    projectActive(q_.data(), uC_.data());
    projectActive(qPrev_.data(), uCPrev_.data());
    pickup_ = kernels::dot(h_.data(), q_.data(), Ma_);
}

void ModalSolver::setInitialDisplacement(const std::vector<double>& modalDisplacement)
{
    if (static_cast<int>(modalDisplacement.size()) != M_)
        throw std::invalid_argument("initial displacement has the wrong number of modes");
    std::vector<double> previous(M_, 0.0);
    for (int p = 0; p < M_; ++p)
        previous[p] = freeDampedMotion(modalDisplacement[p], 0.0, omega_[p], sigma_[p], -dt_);
    setState(modalDisplacement, previous);
}

void ModalSolver::predict()
{
    // q~ = a q - e q^{n-1}, written over q^{n-1}; the pickup (and, for one point, the contact
    // displacement) of q~ in the same pass over the modes.
    const bool onePoint = P_ == 1 && !transform_;
    double contact = 0.0;
    if (onePoint && pendingCorrection_ != 0.0)
    {
        kernels::predictCorrected(a_.data(), e_.data(), q_.data(), qPrev_.data(), h_.data(), phi_.data(),
                                  pendingCorrection_, Ma_, pickupTilde_, contact);
        pendingCorrection_ = 0.0;
    }
    else
        kernels::predict(a_.data(), e_.data(), q_.data(), qPrev_.data(), h_.data(), onePoint ? phi_.data() : nullptr,
                         Ma_, pickupTilde_, contact);
    if (onePoint)
        uTilde_[0] = contact;
    else if (!transform_)
        for (int j = 0; j < P_; ++j)
            uTilde_[j] = kernels::dot(phi_.data() + size_t(j) * Ma_, qPrev_.data(), Ma_);
}

void ModalSolver::settle()
{
    if (pendingCorrection_ != 0.0)
    {
        kernels::axpy(pendingCorrection_, phi_.data(), q_.data(), Ma_);
        pendingCorrection_ = 0.0;
    }
}

void ModalSolver::step()
{
    predict();
    if (transform_)
    {
        double* in = transform_->in;
        std::copy(qPrev_.begin(), qPrev_.end(), in);
        fftw_execute(transform_->plan);
        for (int j = 0; j < P_; ++j)
            uTilde_[j] = transform_->scale * transform_->out[transform_->nodes[j] - 1];
    }

    bool anyForce = false;
    lastIterations_ = 0;
    if (P_ > 0)
    {
        for (int j = 0; j < P_; ++j)
        {
            s_[j] = contacts_[j].height - uCPrev_[j];
            b_[j] = uTilde_[j] - uCPrev_[j];
        }
        lastIterations_ = system_.solve(s_.data(), b_.data(), r_.data(), slope_.data());
        for (int j = 0; j < P_; ++j)
            anyForce = anyForce || slope_[j] != 0.0;
    }

    double y = pickupTilde_;
    if (anyForce)
    {
        // q^{n+1} = q~ + (dt^2/mu) Phi^T W f with f = -G(r).
        double* next = qPrev_.data();
        if (transform_)
        {
            double* in = transform_->in;
            std::fill(in, in + M_, 0.0);
            for (int j = 0; j < P_; ++j)
                in[transform_->nodes[j] - 1] = -contacts_[j].weight * slope_[j];
            fftw_execute(transform_->plan);
            kernels::axpy(forceScale_ * transform_->scale, transform_->out, next, M_);
        }
        else if (P_ == 1)
            pendingCorrection_ = -forceScale_ * contacts_[0].weight * slope_[0];  // applied in the next pass
        else
            for (int j = 0; j < P_; ++j)
                if (slope_[j] != 0.0)
                    kernels::axpy(-forceScale_ * contacts_[j].weight * slope_[j], phi_.data() + size_t(j) * Ma_, next, Ma_);
        const auto& A = system_.coupling();
        for (int j = 0; j < P_; ++j)
        {
            double Af = 0.0;
            for (int i = 0; i < P_; ++i)
                Af -= A(j, i) * slope_[i];
            uTilde_[j] += Af;  // u_C^{n+1} = u~ + A f
            y -= pickupPhiW_[j] * slope_[j];
        }
    }

    lastPenetration_ = -std::numeric_limits<double>::infinity();
    for (int j = 0; j < P_; ++j)
    {
        uCPrev_[j] = uC_[j];
        uC_[j] = uTilde_[j];
        lastPenetration_ = std::max(lastPenetration_, contacts_[j].height - uC_[j]);
    }
    std::swap(q_, qPrev_);
    pickup_ = y;
}

std::vector<double> ModalSolver::modalState(bool previous)
{
    settle();
    std::vector<double> full(M_, 0.0);
    const auto& src = previous ? qPrev_ : q_;
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
        u[j] = kernels::dot(phi_.data() + size_t(j) * Ma_, qActive, Ma_);
}

void ModalSolver::contactDisplacement(const double* q, double* u) const
{
    if (transform_)
    {
        projectActive(q, u);  // all modes are active in the transform path
        return;
    }
    for (int j = 0; j < P_; ++j)
        u[j] = kernels::dot(shapes_.data() + size_t(j) * M_, q, M_);
}

double ModalSolver::modalEnergy(const double* next, const double* current) const
{
    double sum = 0.0;
    for (int p = 0; p < M_; ++p)
    {
        const double v = (next[p] - current[p]) / dt_;
        sum += coeffs_[p].kineticWeight * v * v + coeffs_[p].potentialWeight * next[p] * current[p];
    }
    return 0.5 * mu_ * sum;
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

double ModalSolver::contactEnergy(const double* next, const double* current) const
{
    std::vector<double> u(P_), uPrev(P_);
    contactDisplacement(next, u.data());
    contactDisplacement(current, uPrev.data());
    double sum = 0.0;
    for (int j = 0; j < P_; ++j)
        sum += contacts_[j].weight * 0.5
               * (contactPotential(contacts_[j].law, contacts_[j].height - u[j])
                  + contactPotential(contacts_[j].law, contacts_[j].height - uPrev[j]));
    return sum;
}

ModalSolver::Energy ModalSolver::energy()
{
    settle();
    Energy out;
    std::vector<double> u(P_), uPrev(P_);
    projectActive(q_.data(), u.data());
    projectActive(qPrev_.data(), uPrev.data());
    for (int j = 0; j < P_; ++j)
        out.contact += contacts_[j].weight * 0.5
                       * (contactPotential(contacts_[j].law, contacts_[j].height - u[j])
                          + contactPotential(contacts_[j].law, contacts_[j].height - uPrev[j]));
    double sum = 0.0;
    for (int i = 0; i < Ma_; ++i)
    {
        const auto& c = activeCoeffs_[i];
        const double v = (q_[i] - qPrev_[i]) / dt_;
        sum += c.kineticWeight * v * v + c.potentialWeight * q_[i] * qPrev_[i];
    }
    out.total = 0.5 * mu_ * sum + out.contact;
    return out;
}

}  // namespace jawari
