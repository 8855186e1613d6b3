#include "physics/string/RankOneEigen.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

namespace jawari
{

namespace
{
constexpr double kEps = std::numeric_limits<double>::epsilon();

// A plane rotation of the deflation on sorted positions a and b: the columns (q_a, q_b) of the
// basis become (c q_a + s q_b, c q_b - s q_a), which leaves position a without weight.
struct Rotation
{
    int a, b;
    double c, s;
};

// The problem in ascending d, deflated: A = P Q (diag(d) + w w^T) Q^T P^T up to rounding, P the
// sort's permutation and Q the rotations' product.
struct Deflation
{
    std::vector<int> order;     // sorted position -> the entry of the caller's d
    std::vector<double> d, w;   // by sorted position, rotated; w = 0 where deflated
    std::vector<int> kept;      // the positions of the secular equation, d strictly ascending
    std::vector<int> deflated;  // the positions whose eigenpair is (d, e)
    std::vector<Rotation> rotations;
};

// LAPACK dlaed2's tests, in the weights w = sqrt(c) r: dropping w_p perturbs A by about |w| |w_p|,
// and rotating a pair leaves an off-diagonal t c s (t the pair's distance); either is dropped when
// below 8 eps |A|.
Deflation deflate(const std::vector<double>& d, const std::vector<double>& w)
{
    const int N = static_cast<int>(d.size());
    Deflation out;
    out.order.resize(size_t(N));
    std::iota(out.order.begin(), out.order.end(), 0);
    std::stable_sort(out.order.begin(), out.order.end(), [&](int i, int j) { return d[size_t(i)] < d[size_t(j)]; });
    double norm2 = 0.0, largest = 0.0;
    for (const int i : out.order)
    {
        out.d.push_back(d[size_t(i)]);
        out.w.push_back(w[size_t(i)]);
        norm2 += w[size_t(i)] * w[size_t(i)];
        largest = std::max(largest, std::abs(d[size_t(i)]));
    }
    const double norm = std::sqrt(norm2), tolerance = 8.0 * kEps * std::max(largest, norm2);
    int previous = -1;  // the last position with weight, not yet placed
    for (int p = 0; p < N; ++p)
    {
        auto& wp = out.w[size_t(p)];
        if (norm * std::abs(wp) <= tolerance)
        {
            wp = 0.0;
            out.deflated.push_back(p);
            continue;
        }
        if (previous >= 0)
        {
            auto& wq = out.w[size_t(previous)];
            const double tau = std::hypot(wp, wq), c = wp / tau, s = -wq / tau;
            auto &dq = out.d[size_t(previous)], &dp = out.d[size_t(p)];
            if (std::abs((dp - dq) * c * s) <= tolerance)
            {
                out.rotations.push_back({previous, p, c, s});
                const double rotated = dq * c * c + dp * s * s;
                dp = dq * s * s + dp * c * c;
                dq = rotated;
                wp = tau;
                wq = 0.0;
                out.deflated.push_back(previous);
            }
            else
                out.kept.push_back(previous);
        }
        previous = p;
    }
    if (previous >= 0)
        out.kept.push_back(previous);
    return out;
}

// The secular equation of the kept entries: poles d (ascending), weights w2 = w^2.
struct Secular
{
    std::vector<double> d, w2;
    int size() const { return static_cast<int>(d.size()); }
};

// An eigenvalue as its nearer pole plus a shift: lambda = d[origin] + tau.
struct Root
{
    int origin;
    double tau;
};

// d_i - lambda without cancellation.
double distance(const Secular& s, int i, const Root& root)
{
    return (s.d[size_t(i)] - s.d[size_t(root.origin)]) - root.tau;
}

// The secular function's two sums at lambda = d[origin] + x, split at a pole: psi over the poles
// 0..split, phi over the rest, their derivatives, and the sum of the terms' magnitudes (the
// rounding of f is a few eps times it).
struct SecularSums
{
    double psi = 0.0, dpsi = 0.0, phi = 0.0, dphi = 0.0, magnitude = 0.0;
};

SecularSums secularSums(const Secular& s, int split, int origin, double x)
{
    SecularSums sums;
    const double o = s.d[size_t(origin)];
    for (int p = 0; p <= split; ++p)
    {
        const double inverse = 1.0 / ((s.d[size_t(p)] - o) - x), term = s.w2[size_t(p)] * inverse;
        sums.psi += term;
        sums.dpsi += term * inverse;
    }
    for (int p = split + 1; p < s.size(); ++p)
    {
        const double inverse = 1.0 / ((s.d[size_t(p)] - o) - x), term = s.w2[size_t(p)] * inverse;
        sums.phi += term;
        sums.dphi += term * inverse;
    }
    sums.magnitude = sums.phi - sums.psi;  // psi's terms are negative, phi's positive, where x lies
    return sums;
}

// The next shift for root k < n-1 by the fixed-weight rational model: psi ~ p + q/(delta_k - x) and
// phi ~ r + s/(delta_{k+1} - x), each matching value and slope at x; the model's root in the
// interval solves C (delta_k - x)(delta_{k+1} - x) + q (delta_{k+1} - x) + s (delta_k - x) = 0,
// C = 1 + p + r, a quadratic whose root between the poles is 2 W h / (B + sqrt(B^2 - 4 C W h)),
// with the origin's pole at 0, W its weight, h the other pole, B = C h + q + s (no cancellation).
double interiorStep(const Secular& s, int k, int origin, double x, const SecularSums& sums)
{
    const double o = s.d[size_t(origin)];
    const double toK = (s.d[size_t(k)] - o) - x, toNext = (s.d[size_t(k + 1)] - o) - x;
    const double q = sums.dpsi * toK * toK, p = sums.psi - sums.dpsi * toK;
    const double sWeight = sums.dphi * toNext * toNext, r = sums.phi - sums.dphi * toNext;
    const double C = 1.0 + p + r;
    const double W = origin == k ? q : sWeight;
    const double h = origin == k ? s.d[size_t(k + 1)] - o : s.d[size_t(k)] - o;
    const double B = C * h + q + sWeight;
    return 2.0 * W * h / (B + std::sqrt(std::max(0.0, B * B - 4.0 * C * W * h)));
}

// Root k of the secular equation, bracketed and safeguarded by bisection. Between two poles the
// origin is the nearer (the sign of f at the midpoint); above the last pole it is the last pole,
// and psi ~ p - q/x, more concave than psi (every pole at or below 0), puts every step above the
// root, descending onto it.
Root secularRoot(const Secular& s, int k, double rho)
{
    const int n = s.size();
    const bool last = k == n - 1;
    Root root{k, 0.0};
    double lo = 0.0, hi = rho;
    if (!last)
    {
        const double gap = s.d[size_t(k + 1)] - s.d[size_t(k)];
        const auto mid = secularSums(s, k, k, 0.5 * gap);
        const bool left = 1.0 + mid.psi + mid.phi >= 0.0;
        root.origin = left ? k : k + 1;
        lo = left ? 0.0 : -0.5 * gap;
        hi = left ? 0.5 * gap : 0.0;
    }
    double x = last || root.origin == k ? hi : lo;  // the midpoint, or d_max + rho
    for (int iteration = 0; iteration < 400; ++iteration)
    {
        const auto sums = secularSums(s, last ? n - 1 : k, root.origin, x);
        const double f = 1.0 + sums.psi + sums.phi;
        (f < 0.0 ? lo : hi) = x;
        const double noise = kEps * (10.0 * (1.0 + sums.magnitude) + std::abs(x) * (sums.dpsi + sums.dphi));
        if (std::abs(f) <= noise || hi - lo <= 2.0 * kEps * std::max(std::abs(lo), std::abs(hi)))
            break;
        double next = 0.0;
        if (last)
        {
            const double q = sums.dpsi * x * x, onePlusP = 1.0 + sums.psi + sums.dpsi * x;
            next = onePlusP > 0.0 ? q / onePlusP : hi;
        }
        else
            next = interiorStep(s, k, root.origin, x, sums);
        if (!(next > lo && next < hi))
            next = 0.5 * (lo + hi);
        if (next == x)
            break;
        x = next;
    }
    root.tau = x;
    return root;
}

// Loewner's weights: those for which the computed eigenvalues are exact,
//   w-hat_i^2 = prod_j (lambda_j - d_i) / prod_{j != i} (d_j - d_i),
// each lambda_j paired with the pole d_j (every ratio positive, the product neither over- nor
// underflowing), with w_i's sign.
std::vector<double> loewnerWeights(const Secular& s, const std::vector<Root>& roots, const std::vector<double>& w)
{
    const int n = s.size();
    std::vector<double> out(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i)
    {
        double product = -distance(s, i, roots[size_t(i)]);
        for (int j = 0; j < i; ++j)
            product *= distance(s, i, roots[size_t(j)]) / (s.d[size_t(i)] - s.d[size_t(j)]);
        for (int j = i + 1; j < n; ++j)
            product *= distance(s, i, roots[size_t(j)]) / (s.d[size_t(i)] - s.d[size_t(j)]);
        out[size_t(i)] = std::copysign(std::sqrt(std::max(0.0, product)), w[size_t(i)]);
    }
    return out;
}

// One eigenpair: root >= 0 a root of the secular equation, else the deflated sorted position.
struct Eigenpair
{
    double value;
    int root, position;
};

// The eigenvector of a pair in the sorted, rotated frame: e_position, or (D - lambda)^{-1} w-hat
// over the kept positions, normalised.
void rotatedEigenvector(const Deflation& deflation, const Secular& s, const std::vector<Root>& roots,
                        const std::vector<double>& weights, const Eigenpair& pair, std::vector<double>& y)
{
    std::fill(y.begin(), y.end(), 0.0);
    if (pair.root < 0)
    {
        y[size_t(pair.position)] = 1.0;
        return;
    }
    double largest = 0.0;
    for (int i = 0; i < s.size(); ++i)
    {
        const double v = weights[size_t(i)] / distance(s, i, roots[size_t(pair.root)]);
        y[size_t(deflation.kept[size_t(i)])] = v;
        largest = std::max(largest, std::abs(v));
    }
    double norm2 = 0.0;
    for (const int p : deflation.kept)
        norm2 += (y[size_t(p)] / largest) * (y[size_t(p)] / largest);
    const double scale = 1.0 / (largest * std::sqrt(norm2));
    for (const int p : deflation.kept)
        y[size_t(p)] *= scale;
}

// The caller's frame: y <- Q y (the rotations, last first), then the sort undone, then the sign
// that makes the largest-magnitude component positive.
void toCallersFrame(const Deflation& deflation, std::vector<double>& y, double* column)
{
    for (auto t = deflation.rotations.rbegin(); t != deflation.rotations.rend(); ++t)
    {
        const double a = y[size_t(t->a)], b = y[size_t(t->b)];
        y[size_t(t->a)] = t->c * a - t->s * b;
        y[size_t(t->b)] = t->s * a + t->c * b;
    }
    size_t largest = 0;
    for (size_t p = 0; p < y.size(); ++p)
        if (std::abs(y[p]) > std::abs(y[largest]))
            largest = p;
    const double sign = y[largest] < 0.0 ? -1.0 : 1.0;
    for (size_t p = 0; p < y.size(); ++p)
        column[deflation.order[p]] = sign * y[p];
}

}  // namespace

RankOneEigen rankOneUpdateEigen(const std::vector<double>& d, const std::vector<double>& r, double c)
{
    if (r.size() != d.size() || !(c >= 0.0))
        throw std::invalid_argument("rank-one update: d and r need one length, and c >= 0");
    const size_t N = d.size();
    std::vector<double> w(N);
    for (size_t p = 0; p < N; ++p)
        w[p] = std::sqrt(c) * r[p];
    const Deflation deflation = deflate(d, w);
    Secular s;
    std::vector<double> keptWeights;
    double rho = 0.0;
    for (const int p : deflation.kept)
    {
        const double wp = deflation.w[size_t(p)];
        s.d.push_back(deflation.d[size_t(p)]);
        s.w2.push_back(wp * wp);
        keptWeights.push_back(wp);
        rho += wp * wp;
    }
    std::vector<Root> roots;
    std::vector<Eigenpair> pairs;
    for (int k = 0; k < s.size(); ++k)
    {
        roots.push_back(secularRoot(s, k, rho));
        pairs.push_back({s.d[size_t(roots.back().origin)] + roots.back().tau, k, deflation.kept[size_t(k)]});
    }
    for (const int p : deflation.deflated)
        pairs.push_back({deflation.d[size_t(p)], -1, p});
    std::stable_sort(pairs.begin(), pairs.end(), [](const Eigenpair& a, const Eigenpair& b) {
        return a.value < b.value || (a.value == b.value && a.position < b.position);
    });
    const auto weights = loewnerWeights(s, roots, keptWeights);
    RankOneEigen out;
    out.eigenvectors.resize(N * N);
    std::vector<double> y(N);
    for (size_t k = 0; k < N; ++k)
    {
        out.eigenvalues.push_back(pairs[k].value);
        rotatedEigenvector(deflation, s, roots, weights, pairs[k], y);
        toCallersFrame(deflation, y, out.eigenvectors.data() + k * N);
    }
    return out;
}

}  // namespace jawari
