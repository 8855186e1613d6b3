#include "offline/DstTransform.h"

#include "offline/FftwPlanner.h"
#include "physics/modes/ModalKernels.h"

#include <fftw3.h>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <stdexcept>
#include <string>

namespace jawari
{
namespace
{

// S v = scale RODFT00(v) and S^T likewise, with scale = sqrt(2/L) / 2.
class DstTransform final : public GridTransform
{
public:
    DstTransform(std::vector<int> nodes, double lengthMetres, int modes)
        : size_(modes)
        , nodes_(std::move(nodes))
        , scale_(0.5 * std::sqrt(2.0 / lengthMetres))
    {
        in_ = fftw_alloc_real(size_);
        out_ = fftw_alloc_real(size_);
        asideIn_ = fftw_alloc_real(size_);
        asideOut_ = fftw_alloc_real(size_);
        // FFTW_ESTIMATE: the plan is chosen without timing, so a render is the same bit for bit
        // every run (measured plans differ between runs in the last bits), at the same speed here.
        std::lock_guard<std::mutex> lock(fftwPlannerMutex());
        plan_ = fftw_plan_r2r_1d(size_, in_, out_, FFTW_RODFT00, FFTW_ESTIMATE);
        if (plan_ == nullptr)
            throw std::runtime_error("FFTW could not plan a DST-I of size " + std::to_string(size_));
    }
    ~DstTransform() override
    {
        {
            std::lock_guard<std::mutex> lock(fftwPlannerMutex());
            fftw_destroy_plan(plan_);
        }
        fftw_free(in_);
        fftw_free(out_);
        fftw_free(asideIn_);
        fftw_free(asideOut_);
    }
    DstTransform(const DstTransform&) = delete;
    DstTransform& operator=(const DstTransform&) = delete;

    void sample(const double* q, double* u) override
    {
        std::copy(q, q + size_, in_);
        fftw_execute(plan_);
        for (size_t j = 0; j < nodes_.size(); ++j)
            u[j] = scale_ * out_[nodes_[j] - 1];
    }

    void sampleAside(const double* q, double* u) const override
    {
        std::copy(q, q + size_, asideIn_);
        fftw_execute_r2r(plan_, asideIn_, asideOut_);
        for (size_t j = 0; j < nodes_.size(); ++j)
            u[j] = scale_ * asideOut_[nodes_[j] - 1];
    }

    void spread(const double* F, double factor, double* q) override
    {
        std::fill(in_, in_ + size_, 0.0);
        for (size_t j = 0; j < nodes_.size(); ++j)
            in_[nodes_[j] - 1] = F[j];
        fftw_execute(plan_);
        kernels::axpy(factor * scale_, out_, q, size_);
    }

private:
    int size_;
    std::vector<int> nodes_;  // grid node of contact point j
    double scale_;
    fftw_plan plan_ = nullptr;
    double* in_ = nullptr;
    double* out_ = nullptr;
    double* asideIn_ = nullptr;  // sampleAside()'s own buffers
    double* asideOut_ = nullptr;
};

}  // namespace

std::vector<int> distinctGridNodes(const std::vector<ContactPoint>& contacts, double lengthMetres, int modes)
{
    const int N = modes + 1;
    const double dx = lengthMetres / N;
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

void chooseContactPath(ModalSolverConfig& config, ContactPath path)
{
    const int M = config.modes.size();
    const int P = static_cast<int>(config.contacts.size());
    const bool gridAllows = P > 0 && !distinctGridNodes(config.contacts, config.lengthMetres, M).empty();
    if (path == ContactPath::transform && !gridAllows)
        throw std::invalid_argument(
            "the transform path needs every contact point on a distinct node of the grid x_i = i L/(M+1)");
    const bool useTransform =
        path == ContactPath::transform || (path == ContactPath::automatic && gridAllows && P > 24);
    config.transform = nullptr;
    if (useTransform)
        config.transform = [](const std::vector<ContactPoint>& contacts, double lengthMetres, int modes) {
            return std::make_unique<DstTransform>(distinctGridNodes(contacts, lengthMetres, modes), lengthMetres,
                                                  modes);
        };
}

}  // namespace jawari
