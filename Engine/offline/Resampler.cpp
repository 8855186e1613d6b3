#include "offline/Resampler.h"

#include <soxr.h>

#include <stdexcept>
#include <string>

namespace jawari
{

Resampler::Resampler(double inputRateHz, double outputRateHz)
{
    soxr_error_t error = nullptr;
    const soxr_io_spec_t io = soxr_io_spec(SOXR_FLOAT64_I, SOXR_FLOAT64_I);
    const soxr_quality_spec_t quality = soxr_quality_spec(SOXR_VHQ | SOXR_LINEAR_PHASE, SOXR_DOUBLE_PRECISION);
    const soxr_runtime_spec_t runtime = soxr_runtime_spec(1);
    soxr_ = soxr_create(inputRateHz, outputRateHz, 1, &error, &io, &quality, &runtime);
    if (error != nullptr || soxr_ == nullptr)
        throw std::runtime_error(std::string("cannot create the output resampler: ") + (error ? error : "unknown"));
    buffer_.resize(8192);
}

Resampler::~Resampler()
{
    soxr_delete(soxr_);
}

void Resampler::push(const double* input, size_t count, std::vector<double>& out)
{
    while (count > 0)
    {
        size_t used = 0, produced = 0;
        const soxr_error_t error = soxr_process(soxr_, input, count, &used, buffer_.data(), buffer_.size(), &produced);
        if (error != nullptr)
            throw std::runtime_error(std::string("resampler: ") + error);
        out.insert(out.end(), buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(produced));
        input += used;
        count -= used;
        if (used == 0 && produced == 0)
            break;
    }
}

void Resampler::finish(std::vector<double>& out)
{
    for (;;)
    {
        size_t produced = 0;
        const soxr_error_t error = soxr_process(soxr_, nullptr, 0, nullptr, buffer_.data(), buffer_.size(), &produced);
        if (error != nullptr)
            throw std::runtime_error(std::string("resampler: ") + error);
        if (produced == 0)
            break;
        out.insert(out.end(), buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(produced));
    }
}

}  // namespace jawari
