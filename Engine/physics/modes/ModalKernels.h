#pragma once
// The per-mode streams of a step, written for the vector units. RT, no allocation.
//
// A plain `omp simd reduction` keeps one vector accumulator, so the dot products run at the FMA
// latency (one vector every ~4 cycles). Four vectors' worth of independent partial sums
// (kBlock lanes) lets the loads and FMAs overlap; the summation order is fixed, so results are
// reproducible for a given build.

#include <algorithm>
#include <cstddef>

namespace jawari::kernels
{

inline constexpr int kBlock = 32;  // 4 x 8 doubles (AVX-512) or 8 x 4 (AVX2)

// Eight partial sums (one vector) added as a tree, in a fixed order.
inline double sum8(const double* v)
{
    return ((v[0] + v[4]) + (v[2] + v[6])) + ((v[1] + v[5]) + (v[3] + v[7]));
}

// The kBlock partial sums added as a tree (a fixed order): five dependent vector adds instead of
// 31 dependent scalar ones, which cost as much as the whole pass over 200 modes.
inline double horizontalSum(const double* partial)
{
    static_assert(kBlock == 32);
    alignas(64) double t[16];
#pragma omp simd aligned(t : 64)
    for (int k = 0; k < 16; ++k)
        t[k] = partial[k] + partial[k + 16];
#pragma omp simd aligned(t : 64)
    for (int k = 0; k < 8; ++k)
        t[k] += t[k + 8];
    return sum8(t);
}

// q~ = a q - e qPrev written over qPrev, and N readings in the same pass: the first D of q~,
// out[r] = h[r] . q~ (the pickups, a body's bridge), the others of its change over two steps,
// out[r] = h[r] . (q~ - qPrev) (a body's radiated sound). The readings take the first Mh modes
// only (their weights are zero beyond: ModalState::pickupCount(); Mh a multiple of kBlock, or M).
// The single-step path; contact projections follow, after any explicit force has joined q~.
template <int N, int D = N>
inline void predictWith(const double* __restrict a, const double* __restrict e, const double* __restrict current,
                        double* __restrict previous, const double* const* h, int M, int Mh, double* out)
{
    alignas(64) double ph[N][kBlock] = {};
    int p = 0;
    for (; p + kBlock <= Mh; p += kBlock)
    {
#pragma omp simd
        for (int k = 0; k < kBlock; ++k)
        {
            const double old = previous[p + k];
            const double next = a[p + k] * current[p + k] - e[p + k] * old;
            previous[p + k] = next;
            for (int r = 0; r < N; ++r)
                ph[r][k] += h[r][p + k] * (r < D ? next : next - old);
        }
    }
    for (; p + kBlock <= M; p += kBlock)
    {
#pragma omp simd
        for (int k = 0; k < kBlock; ++k)
            previous[p + k] = a[p + k] * current[p + k] - e[p + k] * previous[p + k];
    }
    double y[N];
    for (int r = 0; r < N; ++r)
        y[r] = horizontalSum(ph[r]);
    for (; p < M; ++p)
    {
        const double old = previous[p];
        const double next = a[p] * current[p] - e[p] * old;
        previous[p] = next;
        for (int r = 0; r < N; ++r)
            y[r] += h[r][p] * (r < D ? next : next - old);
    }
    for (int r = 0; r < N; ++r)
        out[r] = y[r];
}

// The same with a pickup h and a second one h2 (or none, null): returns h . q~, and h2 . q~ (or 0)
// into `second`.
inline double predict(const double* a, const double* e, const double* current, double* previous, const double* h,
                      const double* h2, int M, int Mh, double& second)
{
    const double* weights[2] = {h, h2};
    double out[2] = {0.0, 0.0};
    if (h2 != nullptr)
        predictWith<2>(a, e, current, previous, weights, M, Mh, out);
    else
        predictWith<1>(a, e, current, previous, weights, M, Mh, out);
    second = out[1];
    return out[0];
}

// predict() and the contact projections of up to kMaxFused points in the same pass: for k < P,
// u[rows[k]] = phi_j . q~ with j = rows[k] and phi_j at phi + j stride. One read of the state instead
// of 1 + P. M and Mh (the modes the pickups read) multiples of 8. Returns h . q~ (and h2 . q~ into
// `second` when h2 is given).
inline constexpr int kMaxFused = 8;
template <bool Second>
inline double predictProjectWith(const double* __restrict a, const double* __restrict e,
                                 const double* __restrict current, double* __restrict previous,
                                 const double* __restrict h, const double* __restrict h2,
                                 const double* __restrict phi, int stride, const int* __restrict rows, int P, int M,
                                 int Mh, double* __restrict u, double& second)
{
    alignas(64) double ph[8] = {}, ph2[8] = {};
    alignas(64) double pu[kMaxFused][8] = {};
    for (int p = 0; p < M; p += 8)
    {
        alignas(64) double next[8];
#pragma omp simd aligned(next : 64)
        for (int k = 0; k < 8; ++k)
        {
            next[k] = a[p + k] * current[p + k] - e[p + k] * previous[p + k];
            previous[p + k] = next[k];
        }
        if (p < Mh)
        {
#pragma omp simd aligned(ph, ph2, next : 64)
            for (int k = 0; k < 8; ++k)
            {
                ph[k] += h[p + k] * next[k];
                if constexpr (Second)
                    ph2[k] += h2[p + k] * next[k];
            }
        }
        for (int j = 0; j < P; ++j)
        {
            const double* __restrict row = phi + static_cast<ptrdiff_t>(rows[j]) * stride + p;
#pragma omp simd aligned(next : 64)
            for (int k = 0; k < 8; ++k)
                pu[j][k] += row[k] * next[k];
        }
    }
    for (int j = 0; j < P; ++j)
        u[rows[j]] = sum8(pu[j]);
    second = Second ? sum8(ph2) : 0.0;
    return sum8(ph);
}

inline double predictProject(const double* a, const double* e, const double* current, double* previous,
                             const double* h, const double* h2, const double* phi, int stride, const int* rows, int P,
                             int M, int Mh, double* u, double& second)
{
    return h2 != nullptr
             ? predictProjectWith<true>(a, e, current, previous, h, h2, phi, stride, rows, P, M, Mh, u, second)
             : predictProjectWith<false>(a, e, current, previous, h, h2, phi, stride, rows, P, M, Mh, u, second);
}

// u[rows[k]] = phi_j . x (j = rows[k], phi_j at phi + j stride) for k < P <= kMaxFused, in one pass
// over x: the projections predictProject() leaves over. Each row's sum is formed exactly as there, so
// a point's projection does not depend on which pass took it. M a multiple of 8.
inline void projectRows(const double* __restrict phi, int stride, const int* __restrict rows, int P,
                        const double* __restrict x, int M, double* __restrict u)
{
    alignas(64) double pu[kMaxFused][8] = {};
    for (int p = 0; p < M; p += 8)
        for (int j = 0; j < P; ++j)
        {
            const double* __restrict row = phi + static_cast<ptrdiff_t>(rows[j]) * stride + p;
#pragma omp simd aligned(pu : 64)
            for (int k = 0; k < 8; ++k)
                pu[j][k] += row[k] * x[p + k];
        }
    for (int j = 0; j < P; ++j)
        u[rows[j]] = sum8(pu[j]);
}

// projectRows over the modes [from, to) alone, each row's eight partial sums carried in
// lanes[8 j .. 8 j + 8) for j = rows[k] (zero before the first part): one row's sum split over
// several passes, each lane taking its terms in the order projectRows does, so that sum8 of the
// lanes after passes over [0, M) is projectRows' u_j. from and to multiples of 8; any P.
inline void projectRowsPart(const double* __restrict phi, int stride, const int* __restrict rows, int P,
                            const double* __restrict x, int from, int to, double* __restrict lanes)
{
    for (int first = 0; first < P; first += kMaxFused)
    {
        const int count = P - first < kMaxFused ? P - first : kMaxFused;
        alignas(64) double pu[kMaxFused][8];
        for (int j = 0; j < count; ++j)
            for (int k = 0; k < 8; ++k)
                pu[j][k] = lanes[8 * static_cast<ptrdiff_t>(rows[first + j]) + k];
        for (int p = from; p < to; p += 8)
            for (int j = 0; j < count; ++j)
            {
                const double* __restrict row = phi + static_cast<ptrdiff_t>(rows[first + j]) * stride + p;
#pragma omp simd aligned(pu : 64)
                for (int k = 0; k < 8; ++k)
                    pu[j][k] += row[k] * x[p + k];
            }
        for (int j = 0; j < count; ++j)
            for (int k = 0; k < 8; ++k)
                lanes[8 * static_cast<ptrdiff_t>(rows[first + j]) + k] = pu[j][k];
    }
}

// Two steps of a one-point string in one pass (ModalSolver's paired path). The state comes as raw
// predictions with scalar contact corrections still to apply (docs/design.md section 2, with
// q^{n+1} = q~^{n+1} + c phi):
//   q^{m-1} = X + c1 phi,   q^m = Y + (c1 a + c2) phi
// and leaves as X = q~^{m+1} = a q^m - e q^{m-1}, Y = a X - e q^m (q~^{m+2} before step m+1's
// correction, which the caller folds in as c1 a phi), settled = q^m, with h . and phi . of X and Y.
// Per two steps: six loads and three stores per mode, against twelve and four for two single
// steps; the state stays in registers between the steps. phi may be null (no contact point); h2
// (a second pickup) may be null. The pickups read the first Mh modes (a multiple of kBlock, or M).
// partBlocks: the arrays are zero from M to the next multiple of kBlock (padding whose every term
// is +0), M a multiple of 8, and the last modes are taken in blocks of 8 into the lanes they would
// fill in a whole block, so that the sums are a whole block's; without it, one at a time (the tail).
struct PairReadout
{
    double pickup1 = 0.0, contact1 = 0.0, pickup2 = 0.0, contact2 = 0.0;
    double second1 = 0.0, second2 = 0.0;  // h2 . X and h2 . Y
};

// pairStepWith's last modes, from p to M (fewer than a block), one at a time; their sums added to out.
template <bool Second>
inline void pairStepTail(const double* __restrict a, const double* __restrict e, double* __restrict X,
                         double* __restrict Y, double* __restrict settled, const double* __restrict h,
                         const double* __restrict h2, const double* __restrict phi, double c1, double c2, int p,
                         int M, PairReadout& out)
{
    double y1 = out.pickup1, u1 = out.contact1, y2 = out.pickup2, u2 = out.contact2;
    double s1 = out.second1, s2 = out.second2;  // locals: the stores to X and Y cannot alias them
    for (; p < M; ++p)
    {
        const double ph = phi != nullptr ? phi[p] : 0.0;
        const double before = X[p] + c1 * ph;
        const double now = Y[p] + (c1 * a[p] + c2) * ph;
        const double t1 = a[p] * now - e[p] * before;
        const double t2 = a[p] * t1 - e[p] * now;
        settled[p] = now;
        X[p] = t1;
        Y[p] = t2;
        y1 += h[p] * t1;
        u1 += ph * t1;
        y2 += h[p] * t2;
        u2 += ph * t2;
        if constexpr (Second)
        {
            s1 += h2[p] * t1;
            s2 += h2[p] * t2;
        }
    }
    out = {y1, u1, y2, u2, s1, s2};
}

template <bool Second>
inline void pairStepWith(const double* __restrict a, const double* __restrict e, double* __restrict X,
                         double* __restrict Y, double* __restrict settled, const double* __restrict h,
                         const double* __restrict h2, const double* __restrict phi, double c1, double c2, int M, int Mh,
                         bool partBlocks, PairReadout& out)
{
    alignas(64) double ph1[kBlock] = {}, pc1[kBlock] = {}, ph2[kBlock] = {}, pc2[kBlock] = {};
    alignas(64) double sh1[kBlock] = {}, sh2[kBlock] = {};
    static constexpr double zeros[kBlock] = {};
    // Modes p to p + W (W = kBlock, or 8 in a part block), read by the pickups or not, into the
    // partial sums' lanes from p mod kBlock: a part block leaves the lanes of the padding beyond M,
    // whose every term is +0, as they are, so the sums are those of the whole block.
    auto block = [&]<int W, bool Pickups>(int p) {
        const double* __restrict ph = phi != nullptr ? phi + p : zeros;
        const int o = p % kBlock;
#pragma omp simd aligned(ph1, pc1, ph2, pc2, sh1, sh2 : 64)
        for (int k = 0; k < W; ++k)
        {
            const double ak = a[p + k];
            const double before = X[p + k] + c1 * ph[k];
            const double now = Y[p + k] + (c1 * ak + c2) * ph[k];
            const double t1 = ak * now - e[p + k] * before;
            const double t2 = ak * t1 - e[p + k] * now;
            settled[p + k] = now;
            X[p + k] = t1;
            Y[p + k] = t2;
            pc1[o + k] += ph[k] * t1;
            pc2[o + k] += ph[k] * t2;
            if constexpr (Pickups)
            {
                ph1[o + k] += h[p + k] * t1;
                ph2[o + k] += h[p + k] * t2;
                if constexpr (Second)
                {
                    sh1[o + k] += h2[p + k] * t1;
                    sh2[o + k] += h2[p + k] * t2;
                }
            }
        }
    };
    int p = 0;
    for (; p + kBlock <= std::min(Mh, M); p += kBlock)
        block.template operator()<kBlock, true>(p);
    for (; p + kBlock <= M; p += kBlock)
        block.template operator()<kBlock, false>(p);
    for (; partBlocks && p + 8 <= M; p += 8)
        p < Mh ? block.template operator()<8, true>(p) : block.template operator()<8, false>(p);
    out = {horizontalSum(ph1), horizontalSum(pc1), horizontalSum(ph2), horizontalSum(pc2),
           Second ? horizontalSum(sh1) : 0.0, Second ? horizontalSum(sh2) : 0.0};
    pairStepTail<Second>(a, e, X, Y, settled, h, h2, phi, c1, c2, p, M, out);
}

inline void pairStep(const double* a, const double* e, double* X, double* Y, double* settled, const double* h,
                     const double* h2, const double* phi, double c1, double c2, int M, int Mh, bool partBlocks,
                     PairReadout& out)
{
    if (h2 != nullptr)
        pairStepWith<true>(a, e, X, Y, settled, h, h2, phi, c1, c2, M, Mh, partBlocks, out);
    else
        pairStepWith<false>(a, e, X, Y, settled, h, h2, phi, c1, c2, M, Mh, partBlocks, out);
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

// t . (x + y): a symmetric filter's output with the pairs of samples it weights equally.
inline double pairedDot(const double* __restrict t, const double* __restrict x, const double* __restrict y, int M)
{
    alignas(64) double partial[kBlock] = {};
    int p = 0;
    for (; p + kBlock <= M; p += kBlock)
    {
#pragma omp simd aligned(partial : 64)
        for (int k = 0; k < kBlock; ++k)
            partial[k] += t[p + k] * (x[p + k] + y[p + k]);
    }
    double s = horizontalSum(partial);
    for (; p < M; ++p)
        s += t[p] * (x[p] + y[p]);
    return s;
}

// y += c x
inline void axpy(double c, const double* __restrict x, double* __restrict y, int M)
{
#pragma omp simd
    for (int p = 0; p < M; ++p)
        y[p] += c * x[p];
}

// y_p *= f_p
inline void scaleEach(const double* __restrict f, double* __restrict y, int M)
{
#pragma omp simd
    for (int p = 0; p < M; ++p)
        y[p] *= f[p];
}

}  // namespace jawari::kernels
