#pragma once
// The per-mode streams of a step, written for the vector units. RT, no allocation.
//
// A plain `omp simd reduction` keeps one vector accumulator, so the dot products run at the FMA
// latency (one vector every ~4 cycles). Four vectors' worth of independent partial sums
// (kBlock lanes) lets the loads and FMAs overlap; the summation order is fixed, so results are
// reproducible for a given build.

#include <cstddef>

namespace jawari::kernels
{

inline constexpr int kBlock = 32;  // 4 x 8 doubles (AVX-512) or 8 x 4 (AVX2)

inline double horizontalSum(const double* partial)
{
    double s = 0.0;
    for (int k = 0; k < kBlock; ++k)
        s += partial[k];
    return s;
}

// q~ = a q - e qPrev written over qPrev; returns h . q~ and, when phi is not null, phi . q~.
inline void predict(const double* __restrict a, const double* __restrict e, const double* __restrict current,
                    double* __restrict previous, const double* __restrict h, const double* __restrict phi, int M,
                    double& pickup, double& contact)
{
    alignas(64) double ph[kBlock] = {};
    alignas(64) double pc[kBlock] = {};
    int p = 0;
    if (phi != nullptr)
    {
        for (; p + kBlock <= M; p += kBlock)
        {
#pragma omp simd aligned(ph, pc : 64)
            for (int k = 0; k < kBlock; ++k)
            {
                const double next = a[p + k] * current[p + k] - e[p + k] * previous[p + k];
                previous[p + k] = next;
                ph[k] += h[p + k] * next;
                pc[k] += phi[p + k] * next;
            }
        }
    }
    else
    {
        for (; p + kBlock <= M; p += kBlock)
        {
#pragma omp simd aligned(ph : 64)
            for (int k = 0; k < kBlock; ++k)
            {
                const double next = a[p + k] * current[p + k] - e[p + k] * previous[p + k];
                previous[p + k] = next;
                ph[k] += h[p + k] * next;
            }
        }
    }
    double y = horizontalSum(ph);
    double u = horizontalSum(pc);
    for (; p < M; ++p)
    {
        const double next = a[p] * current[p] - e[p] * previous[p];
        previous[p] = next;
        y += h[p] * next;
        if (phi != nullptr)
            u += phi[p] * next;
    }
    pickup = y;
    contact = u;
}

// The same after applying last step's pending contact correction q += c phi (one point): the
// correction rides along this pass instead of costing a pass of its own.
inline void predictCorrected(const double* __restrict a, const double* __restrict e, double* __restrict current,
                             double* __restrict previous, const double* __restrict h, const double* __restrict phi,
                             double c, int M, double& pickup, double& contact)
{
    alignas(64) double ph[kBlock] = {};
    alignas(64) double pc[kBlock] = {};
    int p = 0;
    for (; p + kBlock <= M; p += kBlock)
    {
#pragma omp simd aligned(ph, pc : 64)
        for (int k = 0; k < kBlock; ++k)
        {
            const double now = current[p + k] + c * phi[p + k];
            current[p + k] = now;
            const double next = a[p + k] * now - e[p + k] * previous[p + k];
            previous[p + k] = next;
            ph[k] += h[p + k] * next;
            pc[k] += phi[p + k] * next;
        }
    }
    double y = horizontalSum(ph);
    double u = horizontalSum(pc);
    for (; p < M; ++p)
    {
        const double now = current[p] + c * phi[p];
        current[p] = now;
        const double next = a[p] * now - e[p] * previous[p];
        previous[p] = next;
        y += h[p] * next;
        u += phi[p] * next;
    }
    pickup = y;
    contact = u;
}

// x . y
inline double dot(const double* __restrict x, const double* __restrict y, int M)
{
    alignas(64) double partial[kBlock] = {};
    int p = 0;
    for (; p + kBlock <= M; p += kBlock)
    {
#pragma omp simd aligned(partial : 64)
        for (int k = 0; k < kBlock; ++k)
            partial[k] += x[p + k] * y[p + k];
    }
    double s = horizontalSum(partial);
    for (; p < M; ++p)
        s += x[p] * y[p];
    return s;
}

// y += c x
inline void axpy(double c, const double* __restrict x, double* __restrict y, int M)
{
#pragma omp simd
    for (int p = 0; p < M; ++p)
        y[p] += c * x[p];
}

}  // namespace jawari::kernels
