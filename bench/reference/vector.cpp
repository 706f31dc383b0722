// Many rays at once with Google Highway. See vector.hpp.
//
// Highway compiles this file once per instruction set (foreach_target.h
// includes it again for each target, inside that target's namespace and
// compiler options); HWY_DYNAMIC_DISPATCH picks the best one this CPU runs.
// No intrinsics are written here: Highway's portable operations only.

#include "vector.hpp"

#include "peak.hpp"

#include <algorithm>

#if RAYKIT_BENCH_HWY

#include <cmath>
#include <limits>

// On x86 only the 8- and 16-float targets and the baseline are compiled: the
// SSE ones would add build time and no row to the report.
#ifndef HWY_DISABLED_TARGETS
#define HWY_DISABLED_TARGETS (HWY_SSSE3 | HWY_SSE4 | HWY_AVX3_DL)
#endif
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "vector.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace raykit::bench::simd {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

#include "lanes-inl.h"

/// lanes-inl.h's operations on Highway vectors of tag D.
template <class D>
struct HwyOps {
    using T = hn::TFromD<D>;
    using V = hn::Vec<D>;
    using M = hn::Mask<D>;
    D d;
    V k(double x) const { return hn::Set(d, static_cast<T>(x)); }
    V neg(V x) const { return hn::Neg(x); }
    V fma(V a, V b, V c) const { return hn::MulAdd(a, b, c); }
    V fms(V a, V b, V c) const { return hn::MulSub(a, b, c); }
    V nfms(V a, V b, V c) const { return hn::NegMulSub(a, b, c); }
    V nfma(V a, V b, V c) const { return hn::NegMulAdd(a, b, c); }
    V sqrt(V x) const { return hn::Sqrt(x); }
    V copysign(V mag, V sign) const { return hn::CopySign(mag, sign); }
    V min(V a, V b) const { return hn::Min(a, b); }
    V max(V a, V b) const { return hn::Max(a, b); }
    M ge(V a, V b) const { return a >= b; }
    M gt(V a, V b) const { return a > b; }
    V select(M m, V a, V b) const { return hn::IfThenElse(m, a, b); }
    V zero_unless(M m, V a) const { return hn::IfThenElseZero(m, a); }
};

/// Rays per block of the double lanes' two passes (below): a block's
/// quadratics (3 doubles a ray, 1.5 KiB) stay in the first-level cache
/// between them.
constexpr std::size_t kBlock = 64;

/// The ten input arrays from ray b on, as plain pointers, taken once per call
/// or block. A loop that indexes the vectors of Rays reloads 9 of the 10
/// pointers from the Rays object on every step (GCC 12, Highway's AVX3 and
/// AVX2 targets): the stable float form with 16 lanes took 0.52-0.56 ns a ray
/// that way and takes 0.44-0.48 now, in a test of 4096 rays repeated.
struct Inputs {
    const float *ox, *oy, *oz, *dx, *dy, *dz, *cx, *cy, *cz, *r;
    Inputs(const Rays& in, std::size_t b)
        : ox(in.ox.data() + b), oy(in.oy.data() + b), oz(in.oz.data() + b), dx(in.dx.data() + b),
          dy(in.dy.data() + b), dz(in.dz.data() + b), cx(in.cx.data() + b), cy(in.cy.data() + b),
          cz(in.cz.data() + b), r(in.r.data() + b) {}  // data() + b: valid for an empty range at the end too
};

/// Float lanes: load, compute, store, as many rays per step as a vector holds.
template <LaneRoots<hn::Vec<hn::ScalableTag<float>>, hn::Mask<hn::ScalableTag<float>>> (*F)(
    const HwyOps<hn::ScalableTag<float>>&, hn::Vec<hn::ScalableTag<float>>, hn::Vec<hn::ScalableTag<float>>,
    hn::Vec<hn::ScalableTag<float>>, hn::Vec<hn::ScalableTag<float>>, hn::Vec<hn::ScalableTag<float>>,
    hn::Vec<hn::ScalableTag<float>>, hn::Vec<hn::ScalableTag<float>>, hn::Vec<hn::ScalableTag<float>>,
    hn::Vec<hn::ScalableTag<float>>, hn::Vec<hn::ScalableTag<float>>)>
void FloatLanes(const Rays& in, std::size_t begin, std::size_t end, float* t0, float* t1, float* hit) {
    const hn::ScalableTag<float> d;
    const HwyOps<hn::ScalableTag<float>> o{d};
    const std::size_t n = hn::Lanes(d);
    const Inputs p(in, begin);
    t0 += begin, t1 += begin, hit += begin;
    for (std::size_t j = 0; j < end - begin; j += n) {
        const auto r = F(o, hn::LoadU(d, p.ox + j), hn::LoadU(d, p.oy + j), hn::LoadU(d, p.oz + j),
                         hn::LoadU(d, p.dx + j), hn::LoadU(d, p.dy + j), hn::LoadU(d, p.dz + j),
                         hn::LoadU(d, p.cx + j), hn::LoadU(d, p.cy + j), hn::LoadU(d, p.cz + j),
                         hn::LoadU(d, p.r + j));
        hn::StoreU(r.t0, d, t0 + j);
        hn::StoreU(r.t1, d, t1 + j);
        hn::StoreU(hn::IfThenElseZero(r.hit, hn::Set(d, 2.0f)), d, hit + j);
    }
}

/// lanes-inl.h's operations on two vectors at once, each operation applied
/// to both in turn: the float-float form's chain from load to store is long
/// (about 240 dependent-or-not operations a step, most of them adds), and
/// with one vector a step the out-of-order window holds little more than
/// one step's worth; two independent vectors interleaved operation by
/// operation give it twice the independent work in the same window. Every
/// lane does exactly what it does in HwyOps, so the results are the same bits.
template <class W>
struct Pair {
    W a, b;
};
// At namespace scope, not as friends: Highway's target attributes reach only
// the functions defined in this namespace's region.
template <class W> Pair<W> operator+(Pair<W> x, Pair<W> y) { return {x.a + y.a, x.b + y.b}; }
template <class W> Pair<W> operator-(Pair<W> x, Pair<W> y) { return {x.a - y.a, x.b - y.b}; }
template <class W> Pair<W> operator*(Pair<W> x, Pair<W> y) { return {x.a * y.a, x.b * y.b}; }
template <class W> Pair<W> operator/(Pair<W> x, Pair<W> y) { return {x.a / y.a, x.b / y.b}; }

template <class D>
struct PairOps {
    using One = hn::Vec<D>;
    using V = Pair<One>;
    using M = Pair<hn::Mask<D>>;
    D d;
    V k(double x) const { const One v = hn::Set(d, static_cast<hn::TFromD<D>>(x)); return {v, v}; }
    V neg(V x) const { return {hn::Neg(x.a), hn::Neg(x.b)}; }
    V fma(V a, V b, V c) const { return {hn::MulAdd(a.a, b.a, c.a), hn::MulAdd(a.b, b.b, c.b)}; }
    V fms(V a, V b, V c) const { return {hn::MulSub(a.a, b.a, c.a), hn::MulSub(a.b, b.b, c.b)}; }
    V nfms(V a, V b, V c) const { return {hn::NegMulSub(a.a, b.a, c.a), hn::NegMulSub(a.b, b.b, c.b)}; }
    V nfma(V a, V b, V c) const { return {hn::NegMulAdd(a.a, b.a, c.a), hn::NegMulAdd(a.b, b.b, c.b)}; }
    V sqrt(V x) const { return {hn::Sqrt(x.a), hn::Sqrt(x.b)}; }
    V copysign(V m, V s) const { return {hn::CopySign(m.a, s.a), hn::CopySign(m.b, s.b)}; }
    V min(V a, V b) const { return {hn::Min(a.a, b.a), hn::Min(a.b, b.b)}; }
    V max(V a, V b) const { return {hn::Max(a.a, b.a), hn::Max(a.b, b.b)}; }
    M ge(V a, V b) const { return {a.a >= b.a, a.b >= b.b}; }
    M gt(V a, V b) const { return {a.a > b.a, a.b > b.b}; }
    V select(M m, V a, V b) const { return {hn::IfThenElse(m.a, a.a, b.a), hn::IfThenElse(m.b, a.b, b.b)}; }
    V zero_unless(M m, V a) const { return {hn::IfThenElseZero(m.a, a.a), hn::IfThenElseZero(m.b, a.b)}; }
};

/// The float-float form two vectors of rays a step (PairOps), one at the end
/// when a single vector's worth is left.
void ExactFloatPairs(const Rays& in, std::size_t begin, std::size_t end, float* t0, float* t1, float* hit) {
    using D = hn::ScalableTag<float>;
    const D d;
    const PairOps<D> o2{d};
    const std::size_t n = hn::Lanes(d);
    const Inputs p(in, begin);
    t0 += begin, t1 += begin, hit += begin;
    const std::size_t size = end - begin;
    std::size_t j = 0;
    for (; j + 2 * n <= size; j += 2 * n) {
        auto load = [&](const float* x) { return typename PairOps<D>::V{hn::LoadU(d, x + j), hn::LoadU(d, x + j + n)}; };
        const auto r = lanes_exact_float(o2, load(p.ox), load(p.oy), load(p.oz), load(p.dx), load(p.dy), load(p.dz),
                                         load(p.cx), load(p.cy), load(p.cz), load(p.r));
        hn::StoreU(r.t0.a, d, t0 + j);
        hn::StoreU(r.t0.b, d, t0 + j + n);
        hn::StoreU(r.t1.a, d, t1 + j);
        hn::StoreU(r.t1.b, d, t1 + j + n);
        hn::StoreU(hn::IfThenElseZero(r.hit.a, hn::Set(d, 2.0f)), d, hit + j);
        hn::StoreU(hn::IfThenElseZero(r.hit.b, hn::Set(d, 2.0f)), d, hit + j + n);
    }
    if (j < size) FloatLanes<&lanes_exact_float<HwyOps<D>>>(in, begin + j, end, t0 - begin, t1 - begin, hit - begin);
}

using DoubleTag = hn::ScalableTag<double>;
using DoubleV = hn::Vec<DoubleTag>;
using DoubleOps = HwyOps<DoubleTag>;
/// A formulation's first stage (lanes-inl.h: half_b_quadratic, lagrange_quadratic) ...
using QuadraticStage = Quadratic<DoubleV> (*)(const DoubleOps&, DoubleV, DoubleV, DoubleV, DoubleV, DoubleV,
                                              DoubleV, DoubleV, DoubleV, DoubleV, DoubleV);
/// ... and its second (roots_over, roots_times).
using RootStage = LaneRoots<DoubleV, hn::Mask<DoubleTag>> (*)(const DoubleOps&, const Quadratic<DoubleV>&);

/// Double lanes on float rays: each float is widened exactly, the roots are
/// rounded to float once at the end.
///
/// With kTwoPasses, two passes over each block split at the quadratic: the
/// first widens the ten inputs and computes h, D/4 and the scale, the second
/// takes the square root and the roots and narrows them. The results are
/// those of one pass, bit for bit. Which is faster depends on the form and
/// the core. On the AMD core of an earlier committed run the Lagrange form
/// was faster in two passes (its one-pass loop was one general register short
/// and moved two pointers back from vector registers on every step). On an
/// Intel core with AVX-512, once its sums of products were chains of fused
/// multiply-adds, one pass was faster with both vector widths, by about a
/// fifth, and two passes gained little from the FMAs: in one pass the
/// divider's divides and square roots are spread over the whole loop, in two
/// they are bunched into halves. Half-b, whose two divides fall beside the
/// square root, was faster in one pass on the AMD core too.
template <QuadraticStage Q, RootStage R, bool kTwoPasses>
void DoubleLanes(const Rays& in, std::size_t begin, std::size_t end, float* t0, float* t1, float* hit) {
    const DoubleTag dd;
    const hn::Rebind<float, DoubleTag> df;  // as many floats as dd has doubles
    const DoubleOps o{dd};
    const std::size_t n = hn::Lanes(dd);
    HWY_ALIGN double q[3][kBlock];  // h, D/4, scale: addressed from the stack pointer
    for (std::size_t b = begin; b < end; b += kBlock) {
        const std::size_t size = std::min(kBlock, end - b);  // a multiple of kPad, so of n
        const Inputs p(in, b);
        auto quadratic = [&](std::size_t j) {
            auto load = [&](const float* x) { return hn::PromoteTo(dd, hn::LoadU(df, x + j)); };
            return Q(o, load(p.ox), load(p.oy), load(p.oz), load(p.dx), load(p.dy), load(p.dz), load(p.cx),
                     load(p.cy), load(p.cz), load(p.r));
        };
        auto store = [&](std::size_t j, const LaneRoots<DoubleV, hn::Mask<DoubleTag>>& z) {
            hn::StoreU(hn::DemoteTo(df, z.t0), df, t0 + b + j);
            hn::StoreU(hn::DemoteTo(df, z.t1), df, t1 + b + j);
            hn::StoreU(hn::DemoteTo(df, hn::IfThenElseZero(z.hit, hn::Set(dd, 2.0))), df, hit + b + j);
        };
        if (!kTwoPasses) {
            for (std::size_t j = 0; j < size; j += n) store(j, R(o, quadratic(j)));
            continue;
        }
        for (std::size_t j = 0; j < size; j += n) {
            const Quadratic<DoubleV> z = quadratic(j);
            hn::Store(z.h, dd, &q[0][j]);
            hn::Store(z.disc, dd, &q[1][j]);
            hn::Store(z.scale, dd, &q[2][j]);
        }
        for (std::size_t j = 0; j < size; j += n) {
            store(j, R(o, {hn::Load(dd, &q[0][j]), hn::Load(dd, &q[1][j]), hn::Load(dd, &q[2][j])}));
        }
    }
}

/// The brute-force closest hit over the rectangles, across rays: each lane
/// keeps its own window; the rectangle loop is the same for every lane.
void BoxLanes(const BoxRays& in, std::size_t begin, std::size_t end, const Rect3* rects, int count, float tmin,
              float* t_out, float* rect_out) {
    const hn::ScalableTag<float> d;
    const std::size_t n = hn::Lanes(d);
    const float* o[3] = {in.ox.data(), in.oy.data(), in.oz.data()};
    const float* dir[3] = {in.dx.data(), in.dy.data(), in.dz.data()};
    const auto lo_t = hn::Set(d, tmin);
    for (std::size_t i = begin; i < end; i += n) {
        auto tmax = hn::Set(d, std::numeric_limits<float>::infinity());
        auto best = hn::Set(d, -1.0f);
        for (int k = 0; k < count; ++k) {
            const Rect3& r = rects[k];
            int u, v;
            other_axes(r.axis, u, v);
            const auto t = (hn::Set(d, r.offset) - hn::LoadU(d, o[r.axis] + i)) / hn::LoadU(d, dir[r.axis] + i);
            const auto pu = hn::MulAdd(t, hn::LoadU(d, dir[u] + i), hn::LoadU(d, o[u] + i));
            const auto pv = hn::MulAdd(t, hn::LoadU(d, dir[v] + i), hn::LoadU(d, o[v] + i));
            // The closed window [tmin, tmax]; on a tie the rectangle listed
            // first keeps the hit (the strict t < tmax), as in box.hpp.
            auto in_rect = hn::And(lo_t <= t, t <= tmax);
            in_rect = hn::And(in_rect, hn::And(hn::Set(d, r.lo[0]) <= pu, pu <= hn::Set(d, r.hi[0])));
            in_rect = hn::And(in_rect, hn::And(hn::Set(d, r.lo[1]) <= pv, pv <= hn::Set(d, r.hi[1])));
            const auto take = hn::And(in_rect, hn::Or(best < hn::Zero(d), t < tmax));
            tmax = hn::IfThenElse(take, t, tmax);
            best = hn::IfThenElse(take, hn::Set(d, static_cast<float>(k)), best);
        }
        hn::StoreU(hn::IfThenElseZero(best >= hn::Zero(d), tmax), d, t_out + i);
        hn::StoreU(best, d, rect_out + i);
    }
}

// ---- this target's limits ---------------------------------------------------------

/// 12 independent chains of x = x m + k, fused: the FMA units' pace.
template <class D>
HWY_NOINLINE double FmaChains(D d, long iterations, double seed) {
    using T = hn::TFromD<D>;
    const auto m = hn::Set(d, static_cast<T>(seed)), k = hn::Set(d, static_cast<T>(1 - seed));
    hn::Vec<D> x0 = hn::Set(d, T(1.00)), x1 = hn::Set(d, T(1.01)), x2 = hn::Set(d, T(1.02)),
               x3 = hn::Set(d, T(1.03)), x4 = hn::Set(d, T(1.04)), x5 = hn::Set(d, T(1.05)),
               x6 = hn::Set(d, T(1.06)), x7 = hn::Set(d, T(1.07)), x8 = hn::Set(d, T(1.08)),
               x9 = hn::Set(d, T(1.09)), x10 = hn::Set(d, T(1.10)), x11 = hn::Set(d, T(1.11));
    for (long it = 0; it < iterations; ++it) {
        x0 = hn::MulAdd(x0, m, k), x1 = hn::MulAdd(x1, m, k), x2 = hn::MulAdd(x2, m, k);
        x3 = hn::MulAdd(x3, m, k), x4 = hn::MulAdd(x4, m, k), x5 = hn::MulAdd(x5, m, k);
        x6 = hn::MulAdd(x6, m, k), x7 = hn::MulAdd(x7, m, k), x8 = hn::MulAdd(x8, m, k);
        x9 = hn::MulAdd(x9, m, k), x10 = hn::MulAdd(x10, m, k), x11 = hn::MulAdd(x11, m, k);
    }
    const auto sum = ((x0 + x1) + (x2 + x3)) + ((x4 + x5) + (x6 + x7)) + ((x8 + x9) + (x10 + x11));
    return static_cast<double>(hn::GetLane(sum));
}

/// 8 independent chains of divides (x = m / x) or square roots (x = sqrt(x)).
template <bool Divide, class D>
HWY_NOINLINE double DividerChains(D d, long iterations, double seed) {
    using T = hn::TFromD<D>;
    const auto m = hn::Set(d, static_cast<T>(seed));
    hn::Vec<D> x0 = hn::Set(d, T(1.0)), x1 = hn::Set(d, T(1.1)), x2 = hn::Set(d, T(1.2)),
               x3 = hn::Set(d, T(1.3)), x4 = hn::Set(d, T(1.4)), x5 = hn::Set(d, T(1.5)),
               x6 = hn::Set(d, T(1.6)), x7 = hn::Set(d, T(1.7));
    for (long it = 0; it < iterations; ++it) {
        if (Divide) {  // alternates between two values near 1
            x0 = m / x0, x1 = m / x1, x2 = m / x2, x3 = m / x3, x4 = m / x4, x5 = m / x5, x6 = m / x6, x7 = m / x7;
        } else {  // tends to 1 and stays there
            x0 = hn::Sqrt(x0), x1 = hn::Sqrt(x1), x2 = hn::Sqrt(x2), x3 = hn::Sqrt(x3);
            x4 = hn::Sqrt(x4), x5 = hn::Sqrt(x5), x6 = hn::Sqrt(x6), x7 = hn::Sqrt(x7);
        }
    }
    const auto sum = ((x0 + x1) + (x2 + x3)) + ((x4 + x5) + (x6 + x7));
    return static_cast<double>(hn::GetLane(sum));
}

/// 12 independent chains of x = widen(narrow(x)): the pace of the float <->
/// double conversions, which the double lanes on float rays need once per
/// input and once per result. A pair per step, as neither alone can form a
/// chain; the values stay exactly representable in float.
template <class D>
HWY_NOINLINE double ConvertChains(D d, long iterations, double seed) {
    const hn::Rebind<float, D> f;  // as many floats as d has doubles
    using T = hn::TFromD<D>;
    const T s = static_cast<T>(static_cast<float>(seed));
    hn::Vec<D> x0 = hn::Set(d, s), x1 = hn::Set(d, s + 1), x2 = hn::Set(d, s + 2), x3 = hn::Set(d, s + 3),
               x4 = hn::Set(d, s + 4), x5 = hn::Set(d, s + 5), x6 = hn::Set(d, s + 6), x7 = hn::Set(d, s + 7),
               x8 = hn::Set(d, s + 8), x9 = hn::Set(d, s + 9), x10 = hn::Set(d, s + 10), x11 = hn::Set(d, s + 11);
    auto pair = [&](hn::Vec<D> x) { return hn::PromoteTo(d, hn::DemoteTo(f, x)); };
    for (long it = 0; it < iterations; ++it) {
        x0 = pair(x0), x1 = pair(x1), x2 = pair(x2), x3 = pair(x3), x4 = pair(x4), x5 = pair(x5);
        x6 = pair(x6), x7 = pair(x7), x8 = pair(x8), x9 = pair(x9), x10 = pair(x10), x11 = pair(x11);
    }
    const auto sum = ((x0 + x1) + (x2 + x3)) + ((x4 + x5) + (x6 + x7)) + ((x8 + x9) + (x10 + x11));
    return static_cast<double>(hn::GetLane(sum));
}

/// FmaChains and ConvertChains in one loop. Timed against each alone it
/// shows whether fused multiply-adds and conversions compete for the same
/// issue ports (the mix takes about the sum of their times) or run beside
/// each other (about the longer one); the roofline combines the two terms as
/// measured here (tools/kitlib/bench_report.py).
template <class D>
HWY_NOINLINE double FmaConvertChains(D d, long iterations, double seed) {
    const hn::Rebind<float, D> f;
    using T = hn::TFromD<D>;
    const auto m = hn::Set(d, static_cast<T>(seed)), k = hn::Set(d, static_cast<T>(1 - seed));
    const T s = static_cast<T>(static_cast<float>(seed));
    hn::Vec<D> x0 = hn::Set(d, T(1.00)), x1 = hn::Set(d, T(1.01)), x2 = hn::Set(d, T(1.02)),
               x3 = hn::Set(d, T(1.03)), x4 = hn::Set(d, T(1.04)), x5 = hn::Set(d, T(1.05)),
               x6 = hn::Set(d, T(1.06)), x7 = hn::Set(d, T(1.07)), x8 = hn::Set(d, T(1.08)),
               x9 = hn::Set(d, T(1.09)), x10 = hn::Set(d, T(1.10)), x11 = hn::Set(d, T(1.11));
    hn::Vec<D> y0 = hn::Set(d, s), y1 = hn::Set(d, s + 1), y2 = hn::Set(d, s + 2), y3 = hn::Set(d, s + 3),
               y4 = hn::Set(d, s + 4), y5 = hn::Set(d, s + 5), y6 = hn::Set(d, s + 6), y7 = hn::Set(d, s + 7),
               y8 = hn::Set(d, s + 8), y9 = hn::Set(d, s + 9), y10 = hn::Set(d, s + 10), y11 = hn::Set(d, s + 11);
    auto pair = [&](hn::Vec<D> y) { return hn::PromoteTo(d, hn::DemoteTo(f, y)); };
    for (long it = 0; it < iterations; ++it) {
        x0 = hn::MulAdd(x0, m, k), x1 = hn::MulAdd(x1, m, k), x2 = hn::MulAdd(x2, m, k);
        y0 = pair(y0), y1 = pair(y1), y2 = pair(y2);
        x3 = hn::MulAdd(x3, m, k), x4 = hn::MulAdd(x4, m, k), x5 = hn::MulAdd(x5, m, k);
        y3 = pair(y3), y4 = pair(y4), y5 = pair(y5);
        x6 = hn::MulAdd(x6, m, k), x7 = hn::MulAdd(x7, m, k), x8 = hn::MulAdd(x8, m, k);
        y6 = pair(y6), y7 = pair(y7), y8 = pair(y8);
        x9 = hn::MulAdd(x9, m, k), x10 = hn::MulAdd(x10, m, k), x11 = hn::MulAdd(x11, m, k);
        y9 = pair(y9), y10 = pair(y10), y11 = pair(y11);
    }
    const auto sx = ((x0 + x1) + (x2 + x3)) + ((x4 + x5) + (x6 + x7)) + ((x8 + x9) + (x10 + x11));
    const auto sy = ((y0 + y1) + (y2 + y3)) + ((y4 + y5) + (y6 + y7)) + ((y8 + y9) + (y10 + y11));
    return static_cast<double>(hn::GetLane(sx + sy));
}

/// DividerChains' divides and square roots in one loop, 8 chains of each:
/// timed against each alone, whether the two queue for one divider.
template <class D>
HWY_NOINLINE double DivideSqrtChains(D d, long iterations, double seed) {
    using T = hn::TFromD<D>;
    const auto m = hn::Set(d, static_cast<T>(seed));
    hn::Vec<D> x0 = hn::Set(d, T(1.0)), x1 = hn::Set(d, T(1.1)), x2 = hn::Set(d, T(1.2)),
               x3 = hn::Set(d, T(1.3)), x4 = hn::Set(d, T(1.4)), x5 = hn::Set(d, T(1.5)),
               x6 = hn::Set(d, T(1.6)), x7 = hn::Set(d, T(1.7));
    hn::Vec<D> y0 = x0, y1 = x1, y2 = x2, y3 = x3, y4 = x4, y5 = x5, y6 = x6, y7 = x7;
    for (long it = 0; it < iterations; ++it) {
        x0 = m / x0, x1 = m / x1, x2 = m / x2, x3 = m / x3;
        y0 = hn::Sqrt(y0), y1 = hn::Sqrt(y1), y2 = hn::Sqrt(y2), y3 = hn::Sqrt(y3);
        x4 = m / x4, x5 = m / x5, x6 = m / x6, x7 = m / x7;
        y4 = hn::Sqrt(y4), y5 = hn::Sqrt(y5), y6 = hn::Sqrt(y6), y7 = hn::Sqrt(y7);
    }
    const auto sx = ((x0 + x1) + (x2 + x3)) + ((x4 + x5) + (x6 + x7));
    const auto sy = ((y0 + y1) + (y2 + y3)) + ((y4 + y5) + (y6 + y7));
    return static_cast<double>(hn::GetLane(sx + sy));
}

/// Kernel k(d, iterations, seed): 0 FMA f32, 1 FMA f64, 2 div f32, 3 div f64,
/// 4 sqrt f32, 5 sqrt f64, 6 float <-> double conversion pairs, 7 kernels 1
/// and 6 mixed, 8 kernels 3 and 5 mixed. Returns a value that depends on
/// every chain.
double RunKernel(int k, long iterations, double seed) {
    const hn::ScalableTag<float> f;
    const hn::ScalableTag<double> g;
    switch (k) {
        case 0: return FmaChains(f, iterations, seed);
        case 1: return FmaChains(g, iterations, seed);
        case 2: return DividerChains<true>(f, iterations, seed);
        case 3: return DividerChains<true>(g, iterations, seed);
        case 4: return DividerChains<false>(f, iterations, seed);
        case 5: return DividerChains<false>(g, iterations, seed);
        case 6: return ConvertChains(g, iterations, seed);
        case 7: return FmaConvertChains(g, iterations, seed);
        default: return DivideSqrtChains(g, iterations, seed);
    }
}

void Describe(Target& t) {
    t.name = hwy::TargetName(HWY_TARGET);
    t.lanes_f32 = static_cast<int>(hn::Lanes(hn::ScalableTag<float>()));
    t.lanes_f64 = static_cast<int>(hn::Lanes(hn::ScalableTag<double>()));
    using F = HwyOps<hn::ScalableTag<float>>;
    using G = HwyOps<hn::ScalableTag<double>>;
    t.half_b_f32 = &FloatLanes<&lanes_half_b<F>>;
    t.stable_f32 = &FloatLanes<&lanes_stable<F>>;
    t.exact_f32 = &ExactFloatPairs;
    t.half_b_f64 = &DoubleLanes<&half_b_quadratic<G>, &roots_over<G>, false>;
    t.lagrange_f64 = &DoubleLanes<&lagrange_quadratic<G>, &roots_times<G>, false>;
    t.box_f32 = &BoxLanes;
    t.kernels = &RunKernel;
}

}  // namespace HWY_NAMESPACE
}  // namespace raykit::bench::simd
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace raykit::bench::simd {

HWY_EXPORT(Describe);

namespace {

using Runner = double (*)(int, long, double);

volatile double g_seed = 0.999999;
volatile double g_sink = 0;

/// The best rate of kernel k: operations per nanosecond.
double best_rate(Runner run, int k, double ops_per_iteration, double seconds, int repetitions) {
    long n = 1000;
    for (;;) {  // timed in this thread's CPU time, as peak.cpp does
        const double t0 = thread_cpu_seconds();
        g_sink = run(k, n, g_seed);
        const double s = thread_cpu_seconds() - t0;
        if (s > seconds / 4 || n > (1L << 40)) {
            n = static_cast<long>(static_cast<double>(n) * std::max(1.0, seconds / std::max(s, 1e-9)));
            break;
        }
        n *= 4;
    }
    double best = 0;
    for (int rep = 0; rep < repetitions; ++rep) {
        const double t0 = thread_cpu_seconds();
        g_sink = run(k, n, g_seed);
        const double ns = 1e9 * (thread_cpu_seconds() - t0);
        best = std::max(best, ops_per_iteration * static_cast<double>(n) / ns);
    }
    return best;
}

}  // namespace

std::vector<Target> targets() {
    std::vector<Target> out;
    Target best;
    HWY_DYNAMIC_DISPATCH(Describe)(best);
    out.push_back(best);
#if (HWY_TARGETS & HWY_AVX2) && HWY_ARCH_X86
    // The narrower vectors too, where the best ones are wider: 8 floats
    // against 16 on the same core.
    if ((hwy::SupportedTargets() & HWY_AVX2) && best.name != "AVX2" && best.lanes_f32 > 8) {
        Target avx2;
        N_AVX2::Describe(avx2);
        out.push_back(avx2);
    }
#endif
    return out;
}

void measure(Target& t, double seconds, int repetitions) {
    const Runner run = t.kernels;
    if (!run) return;
    const double lf = t.lanes_f32, ld = t.lanes_f64;
    t.gflops_f32 = std::max(t.gflops_f32, best_rate(run, 0, 12 * 2 * lf, seconds, repetitions));
    t.gflops_f64 = std::max(t.gflops_f64, best_rate(run, 1, 12 * 2 * ld, seconds, repetitions));
    auto per_lane_ns = [&](int k, double lanes) { return 1 / best_rate(run, k, 8 * lanes, seconds, repetitions); };
    auto keep_min = [](double old, double now) { return old > 0 ? std::min(old, now) : now; };
    t.div_ns_f32 = keep_min(t.div_ns_f32, per_lane_ns(2, lf));
    t.div_ns_f64 = keep_min(t.div_ns_f64, per_lane_ns(3, ld));
    t.sqrt_ns_f32 = keep_min(t.sqrt_ns_f32, per_lane_ns(4, lf));
    t.sqrt_ns_f64 = keep_min(t.sqrt_ns_f64, per_lane_ns(5, ld));
    // Two conversions per chain and step.
    t.cvt_ns = keep_min(t.cvt_ns, 1 / best_rate(run, 6, 12 * 2 * ld, seconds, repetitions));
    // How much of the shorter of two kernels' times a loop of both adds to the longer: 0 when they run
    // beside each other, 1 when they take turns on the same units. Per loop step, each kernel alone and
    // mixed, in this call; the least of the calls is kept, as the roofline must not overstate the bound.
    auto step_ns = [&](int k) { return 1 / best_rate(run, k, 1.0, seconds, repetitions); };
    auto overlap = [](double a, double b, double both) {
        return std::clamp((both - std::max(a, b)) / std::min(a, b), 0.0, 1.0);
    };
    auto keep_least = [](double old, double now) { return std::isnan(old) ? now : std::min(old, now); };
    t.shared_fma_cvt = keep_least(t.shared_fma_cvt, overlap(step_ns(1), step_ns(6), step_ns(7)));
    t.shared_div_sqrt = keep_least(t.shared_div_sqrt, overlap(step_ns(3), step_ns(5), step_ns(8)));
}

std::string status() {
    std::string s = "Highway " + std::to_string(HWY_MAJOR) + "." + std::to_string(HWY_MINOR) + "." +
                    std::to_string(HWY_PATCH) + ":";
    for (const Target& t : targets()) s += " " + t.name + " (" + std::to_string(t.lanes_f32) + " floats)";
    return s;
}

}  // namespace raykit::bench::simd
#endif  // HWY_ONCE

#else  // no Highway

namespace raykit::bench::simd {

std::vector<Target> targets() { return {}; }
void measure(Target&, double, int) {}
std::string status() {
    return "Highway 1.0 or later not found (Debian 12 and later: libhwy-dev); the vector rows are skipped";
}

}  // namespace raykit::bench::simd

#endif  // RAYKIT_BENCH_HWY

// The structure-of-arrays copies, with or without Highway.
#if !RAYKIT_BENCH_HWY || HWY_ONCE
namespace raykit::bench::simd {

Rays to_lanes(const std::vector<Sample<float>>& samples) {
    Rays out;
    out.n = samples.size();
    const std::size_t padded = (samples.size() + kPad - 1) / kPad * kPad;
    for (std::size_t i = 0; i < padded; ++i) {
        const Sample<float>& s = samples[std::min(i, samples.size() - 1)];
        out.ox.push_back(s.o.x), out.oy.push_back(s.o.y), out.oz.push_back(s.o.z);
        out.dx.push_back(s.d.x), out.dy.push_back(s.d.y), out.dz.push_back(s.d.z);
        out.cx.push_back(s.c.x), out.cy.push_back(s.c.y), out.cz.push_back(s.c.z);
        out.r.push_back(s.r);
    }
    return out;
}

BoxRays to_lanes(const std::vector<Vec3<float>>& o, const std::vector<Vec3<float>>& d) {
    BoxRays out;
    out.n = o.size();
    const std::size_t padded = (o.size() + kPad - 1) / kPad * kPad;
    for (std::size_t i = 0; i < padded; ++i) {
        const std::size_t j = std::min(i, o.size() - 1);
        out.ox.push_back(o[j].x), out.oy.push_back(o[j].y), out.oz.push_back(o[j].z);
        out.dx.push_back(d[j].x), out.dy.push_back(d[j].y), out.dz.push_back(d[j].z);
    }
    return out;
}

}  // namespace raykit::bench::simd
#endif
