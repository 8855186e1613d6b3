#include "physics/contact/ContactLanes.h"

#include <cmath>
#include <cstring>

#if defined(__AVX512F__)
#include <immintrin.h>
#endif

namespace jawari
{

void ContactLaneBatch::add(const ScalarContactRequest& request)
{
    const int i = count++;
    stiffness[i] = request.law.stiffness;
    s[i] = request.s;
    b[i] = request.b;
    k[i] = request.k;
    knownX[i] = request.known.x;
    knownXAlpha[i] = request.known.xAlpha;
    knownInvX[i] = request.known.invX;
}

namespace
{

// kContactLanes doubles in one GCC vector: the arithmetic is lane by lane, in the register width the
// target has (one AVX-512 register, two AVX2 ones, or scalar code on a portable build).
using Vec = double __attribute__((vector_size(kContactLanes * sizeof(double))));
using Mask = decltype(Vec{} < Vec{});  // per lane: all ones (true) or zero

[[gnu::always_inline]] inline Vec splat(double x)
{
    Vec v;
    for (int i = 0; i < kContactLanes; ++i)
        v[i] = x;
    return v;
}

[[gnu::always_inline]] inline Vec load(const double* p)
{
    Vec v;
    std::memcpy(&v, p, sizeof v);
    return v;
}

[[gnu::always_inline]] inline Vec select(Mask m, Vec a, Vec b) { return m ? a : b; }
[[gnu::always_inline]] inline Vec absolute(Vec x) { return x < 0.0 ? -x : x; }
[[gnu::always_inline]] inline Vec minimum(Vec a, Vec b) { return b < a ? b : a; }  // std::min's choice, lane by lane
[[gnu::always_inline]] inline Vec maximum(Vec a, Vec b) { return a < b ? b : a; }  // std::max's

// The mask as bits, lane i in bit i.
[[gnu::always_inline]] inline unsigned bits(Mask m)
{
#if defined(__AVX512F__)
    static_assert(kContactLanes == 8);
    return _mm512_test_epi64_mask(reinterpret_cast<__m512i>(m), reinterpret_cast<__m512i>(m));
#else
    unsigned out = 0;
    for (int i = 0; i < kContactLanes; ++i)
        out |= (m[i] != 0 ? 1u : 0u) << i;
    return out;
#endif
}

[[gnu::always_inline]] inline bool any(Mask m) { return bits(m) != 0; }

// f(x) on the lanes of `m` (the libm calls the scalar solve makes, where it makes them), else
// `otherwise`; through an array, so the vector is stored and loaded once, not lane by lane.
template <class F>
[[gnu::always_inline]] inline Vec onLanes(Mask m, Vec x, Vec otherwise, F f)
{
    alignas(64) double in[kContactLanes], result[kContactLanes];
    std::memcpy(in, &x, sizeof x);
    std::memcpy(result, &otherwise, sizeof otherwise);
    for (unsigned b = bits(m); b != 0; b &= b - 1)
    {
        const int i = __builtin_ctz(b);
        result[i] = f(in[i]);
    }
    return load(result);
}

// polynomial16 of ContactLaw.cpp (Estrin's scheme), lane by lane.
[[gnu::always_inline]] inline Vec polynomial16(const double* a, Vec x, Vec x2, Vec x4, Vec x8)
{
    Vec p[8];
    for (int k = 0; k < 8; ++k)
        p[k] = a[2 * k] + a[2 * k + 1] * x;
    const Vec q0 = p[0] + p[1] * x2, q1 = p[2] + p[3] * x2, q2 = p[4] + p[5] * x2, q3 = p[6] + p[7] * x2;
    return (q0 + q1 * x4) + (q2 + q3 * x4) * x8;
}

struct Power  // KnownPower, lane by lane
{
    Vec x{}, xAlpha{}, invX{};
};

struct Divided
{
    Vec D{}, dD{}, d2D{};
};

// The lanes' shared law and the solve's fixed inputs.
struct Lanes
{
    const DividedSeries& series;
    double alpha, beta;
    Vec s, b, c, sAlpha, invS;
};

[[gnu::always_inline]] inline Vec anchoredPower(const DividedSeries& series, const Power& anchor, Vec p)
{
    const Vec x = (p - anchor.x) * anchor.invX;
    const Mask ok = (anchor.xAlpha > 0.0) & (absolute(x) <= DividedSeries::kReach);
    const Vec x2 = x * x, x4 = x2 * x2;
    return select(ok, anchor.xAlpha * polynomial16(series.a, x, x2, x4, x4 * x4), splat(0.0));
}

// ContactLaw.cpp's divided() on the lanes of `want`: the series about s where it reaches, else from
// the anchor's power or a pow that renews it.
[[gnu::always_inline]] inline Divided divided(const Lanes& l, Vec r, Power& anchor, Mask want)
{
    const Vec e = -r * l.invS;
    const Mask near = (l.s > 0.0) & (absolute(e) <= DividedSeries::kReach);
    Divided out;
    if (any(want & near))
    {
        const Vec e2 = e * e, e4 = e2 * e2, e8 = e4 * e4;
        const Vec v = polynomial16(l.series.c, e, e2, e4, e8);
        const Vec dv = polynomial16(l.series.c1, e, e2, e4, e8);
        const Vec d2v = polynomial16(l.series.c2, e, e2, e4, e8);
        const Vec scale = l.sAlpha * l.invS;
        out = {l.sAlpha * v, scale * dv, scale * l.invS * d2v};
    }
    const Mask away = want & ~near;
    if (!any(away))
        return out;
    const Vec p = l.s - r, invH = -1.0 / r;
    Vec pAlpha = anchoredPower(l.series, anchor, p);
    const Mask fresh = away & (pAlpha == 0.0);
    if (any(fresh))
    {
        const double alpha = l.alpha;
        pAlpha = onLanes(fresh, p, pAlpha, [alpha](double x) { return lawPower(x, alpha); });
        anchor = {select(fresh, p, anchor.x), select(fresh, pAlpha, anchor.xAlpha), select(fresh, 1.0 / p, anchor.invX)};
    }
    const Vec D = (pAlpha * p - l.sAlpha * maximum(l.s, splat(0.0))) * invH;
    const Vec dD = ((l.alpha + 1.0) * pAlpha - D) * invH;
    const Vec d2D = ((l.alpha + 1.0) * l.alpha * pAlpha / p - 2.0 * dD) * invH;
    return {select(near, out.D, D), select(near, out.dD, dD), select(near, out.d2D, d2D)};
}

// ContactLaw.cpp's contactStart(), lane by lane (pows on the lanes of `want` that take them).
[[gnu::always_inline]] inline Vec contactStart(const Lanes& l, Mask want)
{
    const double alpha = l.alpha, beta = l.beta;
    const Vec s = l.s, b = l.b, c = l.c, sAlpha = l.sAlpha, d = s - b;
    const Mask positive = s > 0.0;
    const Vec cs = c * sAlpha;
    const Vec A2 = cs * l.series.c[2], A1 = cs * l.series.c[1] + s, A0 = cs * l.series.c[0] + b;
    const Vec A1squared = A1 * A1, denominator = A1squared - A0 * A2;
    // The divisions, the costliest vector operations, only where some lane takes their branch.
    const Mask halley = denominator >= 0.5 * A1squared;
    Vec e = -A0 * A1 / denominator;
    if (any(want & positive & ~halley))
        e = select(halley, e, -A0 / A1);
    const Vec model = s * (1.0 + e);
    // Phi(s) > 0: the nearest of the tangent at s, the linear bound and the model.
    const Mask rootBelowS = A0 > 0.0;
    Vec above = model;
    if (any(want & positive & rootBelowS))
    {
        const Vec tangent = s - A0 / (c * beta * alpha / 2.0 * sAlpha / s + 1.0);
        const Vec linear = (d - cs) / (cs / s + 1.0);
        above = select(tangent > 0.0, minimum(tangent, linear), linear);
        above = select((model > 0.0) & (e > -0.5), minimum(above, model), above);
    }
    // Phi(s) <= 0: the model, or the bound c p^alpha = d.
    const Mask bound = want & positive & ~rootBelowS & ~(e <= 1.0);
    Vec below = model;
    if (any(bound))
    {
        const Vec boundRoot = onLanes(bound, d / c, d, [alpha](double x) { return std::pow(x, 1.0 / alpha); });
        below = select(e <= 1.0, model, minimum(d, boundRoot));
    }
    // A new contact: c p^beta = d (d - s).
    Vec fresh = d;
    if (any(want & ~positive))
        fresh = onLanes(want & ~positive, d * (d - s) / c, d, [beta](double x) { return std::pow(x, 1.0 / beta); });
    Vec p = select(positive, select(rootBelowS, above, below), fresh);
    return select((p > 0.0) & (p <= d), p, d);
}

struct Step
{
    Vec step{}, force{};
    Mask far{};
};

// ContactLaw.cpp's contactStep(), lane by lane (log and expm1 on the far lanes of `want`).
[[gnu::always_inline]] inline Step contactStep(const Lanes& l, const Divided& v, Vec r, Mask want)
{
    const Vec p = l.s - r;
    Step out;
    out.force = l.c * v.D;
    const Vec gap = r - l.b;
    const Vec phi = out.force - gap, dPhi = l.c * v.dD + 1.0;
    out.far = (gap > 4.0 * out.force) | ((out.force > 4.0 * gap) & (gap > 0.01 * p));
    const Vec dPhi2 = dPhi * dPhi, denominator = dPhi2 - 0.5 * phi * l.c * v.d2D;
    const Mask halley = denominator >= 0.5 * dPhi2;
    out.step = -phi * dPhi / denominator;
    if (any(want & ~halley))
        out.step = select(halley, out.step, -phi / dPhi);
    const Mask far = want & out.far;
    if (any(far))
    {
        const Vec F = onLanes(far, out.force / gap, splat(0.0), [](double x) { return std::log(x); });
        const Vec dF = p * (v.dD / v.D + 1.0 / gap);
        const Vec farStep = onLanes(far, -F / dF, splat(0.0), [](double x) { return std::expm1(x); });
        out.step = select(far, p * farStep, out.step);
    }
    return out;
}

struct Solved
{
    Vec r{}, slope{};
    Power penetration;
    int iterations[kContactLanes] = {};
};

// The lanes in contact at n+1 (`contact`): solveScalarContact's iteration, every lane until it has
// converged by the scalar test, converged lanes held.
void solveInContact(const Lanes& l, Vec K, Mask contact, Solved& out)
{
    Vec r = maximum(l.s - contactStart(l, contact), l.b);
    Power anchor;
    Divided v = divided(l, r, anchor, contact);
    Mask active = contact;
    constexpr int maxIterations = 100;
    for (int it = 1; it <= maxIterations; ++it)
    {
        for (int i = 0; i < kContactLanes; ++i)
            if (active[i] != 0)
                out.iterations[i] = it;
        const Vec p = l.s - r;
        const Step st = contactStep(l, v, r, active);
        Vec next = r - st.step;
        const Mask low = ~(next >= l.b);  // p <= d, right of the root
        next = select(low, l.b, next);
        const Mask high = ~low & ~(next < l.s);  // the root has p > 0: halve p towards it
        next = select(high, 0.5 * (r + l.s), next);
        const Vec moved = next - r;
        r = select(active, next, r);
        const Mask converged = active & ~st.far & ~(low | high)
                               & (absolute(moved) <= 1e-6 * minimum(p, absolute(r) + absolute(l.b) + st.force));
        v.D = select(converged, v.D - moved * (v.dD - 0.5 * moved * v.d2D), v.D);
        active &= ~converged;
        if (!any(active))
            break;
        const Divided w = divided(l, r, anchor, active);
        v = {select(active, w.D, v.D), select(active, w.dD, v.dD), select(active, w.d2D, v.d2D)};
    }
    out.r = select(contact, r, out.r);
    const Vec slope = -K / l.beta * v.D;
    out.slope = select(contact, slope, out.slope);
    // rootPower(), then the anchor's power where it does not apply.
    const Vec p = l.s - r;
    const Mask rooted = contact & (p >= 0.5 * l.s) & (p > 0.0);
    const Vec D = -(l.alpha + 1.0) * slope / K;
    const Vec invP = 1.0 / p;
    out.penetration = {select(rooted, p, splat(0.0)), select(rooted, (l.sAlpha * l.s - D * r) * invP, splat(0.0)),
                       select(rooted, invP, splat(0.0))};
    const Mask unknown = contact & ~rooted & (p > 0.0);
    if (any(unknown))
    {
        const Vec pAlpha = anchoredPower(l.series, anchor, p);
        const Mask known = unknown & (pAlpha > 0.0);
        out.penetration = {select(known, p, out.penetration.x), select(known, pAlpha, out.penetration.xAlpha),
                           select(known, invP, out.penetration.invX)};
    }
}

}  // namespace

void solveContactLanes(ContactLaneBatch& batch)
{
    const double alpha = batch.exponent, beta = alpha + 1.0;
    Mask used{};
    for (int i = 0; i < kContactLanes; ++i)
        used[i] = i < batch.count ? -1 : 0;
    // Unused lanes: out of contact (s = -1, b = 0).
    const Vec s = select(used, load(batch.s), splat(-1.0)), b = select(used, load(batch.b), splat(0.0));
    const Vec K = select(used, load(batch.stiffness), splat(1.0)), k = select(used, load(batch.k), splat(1.0));
    const Mask out = (s <= 0.0) & (s - b <= 0.0);
    const Vec c = k * K / beta;
    // powerOf(s, alpha, known).
    const Vec knownXAlpha = load(batch.knownXAlpha);
    const Vec x = select(knownXAlpha > 0.0, (s - load(batch.knownX)) * load(batch.knownInvX), splat(1.0));
    const Mask nearKnown = absolute(x) <= 1e-6;
    const Mask positive = s > 0.0;
    Vec sAlpha = knownXAlpha * (1.0 + x * alpha * (1.0 + 0.5 * x * (alpha - 1.0)));
    sAlpha = onLanes(positive & ~nearKnown, s, sAlpha, [alpha](double v) { return lawPower(v, alpha); });
    sAlpha = select(positive, sAlpha, splat(0.0));
    const Vec psiBefore = K / beta * sAlpha * maximum(s, splat(0.0));
    // Leaving the obstacle: the closed form.
    const Mask leaving = ~out & ((s - b) - c * sAlpha <= 0.0);
    Solved solved;
    solved.r = b;
    if (any(leaving))
    {
        const Vec disc = onLanes(leaving, b * b + 4.0 * k * psiBefore, splat(0.0), [](double v) { return std::sqrt(v); });
        const Vec r = select(b >= 0.0, 0.5 * (b + disc), 2.0 * k * psiBefore / (disc - b));
        solved.r = select(leaving, r, solved.r);
        solved.slope = select(leaving, -psiBefore / r, solved.slope);
    }
    const Mask contact = ~out & ~leaving;
    if (any(contact))
    {
        const Vec invS = select(s > 0.0, 1.0 / s, splat(0.0));
        const Lanes lanes{*batch.series, alpha, beta, s, b, c, sAlpha, invS};
        solveInContact(lanes, K, contact, solved);
    }
    for (int i = 0; i < batch.count; ++i)
    {
        auto& sol = batch.solution[i];
        sol.r = solved.r[i];
        sol.slope = solved.slope[i];
        sol.iterations = solved.iterations[i];
        sol.penetration = {solved.penetration.x[i], solved.penetration.xAlpha[i], solved.penetration.invX[i]};
    }
}

}  // namespace jawari
