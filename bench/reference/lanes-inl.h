// Ray-sphere formulations written once for one lane or for many: the same
// template runs on a plain float or double, on Counted<T> (to count its
// arithmetic) and on Google Highway's vectors (bench/vector.cpp), so the
// vector code and its flop count cannot drift apart.
//
// Branch-free on purpose: in a vector every lane takes the same path, so a
// miss does all the arithmetic of a hit and its lane is masked out at the
// end. A formulation gets an `Ops` object that supplies what differs between
// a number and a vector: constants, fused multiply-add, square root, select,
// comparisons (ScalarOps below; HwyOps in vector.cpp).
//
// No include guard: this file is included inside a namespace, once per
// Highway target (vector.cpp re-includes itself for each instruction set, and
// the target's compiler options must apply to these templates), and once for
// scalar code (variants.cpp). It includes nothing itself.
//
// The double forms take float inputs widened to double, exactly; see
// formulations.hpp for the algebra and docs/bench.md for what each costs.

// The helpers below are always inlined: a vector helper left out of line
// (GCC 12 did so with dot2, four calls a step in the float-float form with
// 16 float lanes) passes and returns its vectors through memory.
#ifndef RAYKIT_LANES_INLINE
#if defined(__GNUC__)
#define RAYKIT_LANES_INLINE inline __attribute__((always_inline))
#else
#define RAYKIT_LANES_INLINE inline
#endif
#endif

/// One answer per lane: both roots (zero when missing) and whether it hit.
template <class V, class M>
struct LaneRoots {
    V t0, t1;
    M hit;
};

/// A quadratic a t^2 + 2 h t + c reduced to what its roots need: h, the
/// quarter discriminant D/4 = h^2 - a c, and a or 1/a (as each formulation
/// says). The double-lane kernels (vector.cpp) compute it for a block of rays
/// in one pass and the roots in a second; a single lane runs both in a row.
template <class V>
struct Quadratic {
    V h, disc, scale;
};

/// The half-b form's quadratic: c = f.f - r^2 and D/4 = h^2 - a c; scale = a.
template <class O, class V = typename O::V>
Quadratic<V> half_b_quadratic(const O&, V ox, V oy, V oz, V dx, V dy, V dz, V cx, V cy, V cz, V r) {
    const V fx = ox - cx, fy = oy - cy, fz = oz - cz;
    const V a = dx * dx + dy * dy + dz * dz;
    const V h = fx * dx + fy * dy + fz * dz;
    const V c = fx * fx + fy * fy + fz * fz - r * r;
    return {h, h * h - a * c, a};
}

/// t = (-h -+ sqrt(D/4)) / a, with scale = a: two divides.
template <class O, class V = typename O::V>
LaneRoots<V, typename O::M> roots_over(const O& o, const Quadratic<V>& q) {
    const auto hit = o.ge(q.disc, o.k(0));
    const V root = o.sqrt(o.zero_unless(hit, q.disc));
    return {o.zero_unless(hit, (o.neg(q.h) - root) / q.scale), o.zero_unless(hit, (root - q.h) / q.scale), hit};
}

/// The half-b form: t = (-h -+ sqrt(h^2 - a c)) / a, c = f.f - r^2.
template <class O, class V = typename O::V>
RAYKIT_LANES_INLINE
LaneRoots<V, typename O::M> lanes_half_b(const O& o, V ox, V oy, V oz, V dx, V dy, V dz, V cx, V cy, V cz,
                                         V r) {
    return roots_over(o, half_b_quadratic(o, ox, oy, oz, dx, dy, dz, cx, cy, cz, r));
}

/// The Lagrange-identity discriminant a r^2 - |f x d|^2; scale = 1/a.
template <class O, class V = typename O::V>
Quadratic<V> lagrange_quadratic(const O& o, V ox, V oy, V oz, V dx, V dy, V dz, V cx, V cy, V cz, V r) {
    const V fx = ox - cx, fy = oy - cy, fz = oz - cz;
    const V a = o.fma(dz, dz, o.fma(dy, dy, dx * dx));
    const V h = o.fma(fz, dz, o.fma(fy, dy, fx * dx));
    const V gx = o.fms(fy, dz, fz * dy), gy = o.fms(fz, dx, fx * dz), gz = o.fms(fx, dy, fy * dx);
    // One divide here and two multiplies in roots_times() instead of two
    // divides: the divider is this form's bottleneck in vectors, and in
    // double the extra rounding is far below the float result's half ulp.
    return {h, o.fms(a, r * r, o.fma(gz, gz, o.fma(gy, gy, gx * gx))), o.k(1) / a};
}

/// t = (-h -+ sqrt(D/4)) * (1/a), with scale = 1/a.
template <class O, class V = typename O::V>
LaneRoots<V, typename O::M> roots_times(const O& o, const Quadratic<V>& q) {
    const auto hit = o.ge(q.disc, o.k(0));
    const V root = o.sqrt(o.zero_unless(hit, q.disc));
    const V hs = q.h * q.scale;
    return {o.zero_unless(hit, o.nfms(root, q.scale, hs)), o.zero_unless(hit, o.fms(root, q.scale, hs)), hit};
}

/// The Lagrange-identity discriminant, then as half-b (the kit's reference,
/// step 02, when run in double).
template <class O, class V = typename O::V>
RAYKIT_LANES_INLINE
LaneRoots<V, typename O::M> lanes_lagrange(const O& o, V ox, V oy, V oz, V dx, V dy, V dz, V cx, V cy, V cz,
                                           V r) {
    return roots_times(o, lagrange_quadratic(o, ox, oy, oz, dx, dy, dz, cx, cy, cz, r));
}

/// The stable float form of formulations.hpp: closest-point discriminant and
/// the root pair q / a, c / q.
template <class O, class V = typename O::V>
RAYKIT_LANES_INLINE
LaneRoots<V, typename O::M> lanes_stable(const O& o, V ox, V oy, V oz, V dx, V dy, V dz, V cx, V cy, V cz,
                                         V r) {
    const V fx = ox - cx, fy = oy - cy, fz = oz - cz;
    const V a = dx * dx + dy * dy + dz * dz;
    const V h = fx * dx + fy * dy + fz * dz;
    const V r2 = r * r;
    const V c = fx * fx + fy * fy + fz * fz - r2;
    const V k = h / a;
    const V lx = fx - k * dx, ly = fy - k * dy, lz = fz - k * dz;
    const V disc = a * (r2 - (lx * lx + ly * ly + lz * lz));
    const auto hit = o.ge(disc, o.k(0));
    const V q = o.neg(h + o.copysign(o.sqrt(o.zero_unless(hit, disc)), h));
    const V u = q / a, w = c / q;
    return {o.zero_unless(hit, o.min(u, w)), o.zero_unless(hit, o.max(u, w)), hit};
}

// ---- float-only and exact: error-free transformations --------------------------
//
// A float-float number is an unevaluated sum hi + lo with |lo| <= ulp(hi) / 2.
// TwoSum (Knuth, The Art of Computer Programming vol. 2, 1969) gives a + b
// exactly as s + e; TwoProduct with a fused multiply-add gives a b exactly as
// p + e, e = fma(a, b, -p); dot products in float-float follow Ogita, Rump and
// Oishi, "Accurate sum and dot product" (SIAM J. Sci. Comput., 2005), Dot2;
// the difference of products ad - bc keeps both product errors, as in Kahan's
// FMA algorithm for it (Jeannerod, Louvet and Muller, "Further analysis of
// Kahan's algorithm for the accurate computation of 2x2 determinants", Math.
// Comp., 2013); Dekker ("A floating-point technique for extending the
// available precision", Numer. Math., 1971) for the products of float-floats.

template <class V>
struct FF {
    V hi, lo;
};

/// a + b = s + e exactly (any order of magnitude).
template <class O, class V = typename O::V>
RAYKIT_LANES_INLINE FF<V> two_sum(const O&, V a, V b) {
    const V s = a + b;
    const V bb = s - a;
    return {s, (a - (s - bb)) + (b - bb)};
}

/// a - b = s + e exactly: two_sum(a, -b) without the negation (the same
/// roundings, so the same bits).
template <class O, class V = typename O::V>
RAYKIT_LANES_INLINE FF<V> two_diff(const O&, V a, V b) {
    const V s = a - b;
    const V bb = s - a;
    return {s, (a - (s - bb)) - (b + bb)};
}

/// a b = p + e exactly.
template <class O, class V = typename O::V>
RAYKIT_LANES_INLINE FF<V> two_prod(const O& o, V a, V b) {
    const V p = a * b;
    return {p, o.fms(a, b, p)};
}

/// x.y for three float-float pairs given as hi parts only (x, y floats), in
/// float-float: Dot2, as if computed in twice the precision, then rounded.
template <class O, class V = typename O::V>
RAYKIT_LANES_INLINE FF<V> dot2(const O& o, V x0, V x1, V x2, V y0, V y1, V y2) {
    const FF<V> p0 = two_prod(o, x0, y0), p1 = two_prod(o, x1, y1), p2 = two_prod(o, x2, y2);
    const FF<V> s1 = two_sum(o, p0.hi, p1.hi);
    const FF<V> s2 = two_sum(o, s1.hi, p2.hi);
    return {s2.hi, ((p0.lo + p1.lo) + p2.lo) + (s1.lo + s2.lo)};
}

/// hi + lo renormalised (|hi| >= |lo| assumed: Dekker's FastTwoSum).
template <class O, class V = typename O::V>
RAYKIT_LANES_INLINE FF<V> renorm(const O&, V hi, V lo) {
    const V s = hi + lo;
    return {s, lo - (s - hi)};
}

/// a d - b c + extra, in float-float: both products kept exactly.
template <class O, class V = typename O::V>
RAYKIT_LANES_INLINE FF<V> diff_of_products(const O& o, V a, V d, V b, V c, V extra) {
    const FF<V> p = two_prod(o, a, d), q = two_prod(o, b, c);
    const FF<V> s = two_diff(o, p.hi, q.hi);
    return renorm(o, s.hi, s.lo + ((p.lo - q.lo) + extra));
}

/// Minus the quotient (n.hi + n.lo) / (d.hi + d.lo), to about a float's
/// half ulp, given ninv = -1/d.hi rounded: t = n.hi ninv is within two ulps,
/// the remainder n.hi + t d.hi is exact in one fused multiply-add (Markstein;
/// for a t that close the remainder is a float), and one correction,
/// multiplied by ninv rather than divided by d.hi, adds it: the correction
/// is at most a few ulps of t, so ninv's own rounding (half an ulp of 1/d.hi)
/// changes the result by far less than a float ulp of t. One divide per
/// denominator instead of two per quotient: the divider is the unit this
/// form waits for with 16 float lanes. Negated because the roots are: every
/// step is the mirror image of the quotient's own (round to nearest is
/// symmetric), so the bits are those of negating the quotient, without the
/// negation's instruction.
template <class O, class V = typename O::V>
RAYKIT_LANES_INLINE V minus_quotient(const O& o, V nhi, V nlo, V dhi, V dlo, V ninv) {
    const V t = nhi * ninv;
    return t + (o.fma(t, dhi, nhi) + o.fma(t, dlo, nlo)) * ninv;
}

/// The Lagrange form in float only, made exact with float-float where a
/// rounding would be amplified: f = o - c (TwoSum), a, h, c = f.f - r^2, the
/// cross product and the discriminant a r^2 - |f x d|^2. The square root is
/// refined by one Newton step on the float-float discriminant, the root pair
/// q / a, c / q is formed from float-float q and c, and each quotient gets
/// one correction step (minus_quotient() above). About seven times the flops of
/// the plain form; no double anywhere. Written for the vector units (every
/// operation takes an issue slot there, a negation and a select included):
/// subtractions rather than negated sums, and the roots' sign taken by the
/// reciprocals (minus_quotient), not by negations.
template <class O, class V = typename O::V>
RAYKIT_LANES_INLINE
LaneRoots<V, typename O::M> lanes_exact_float(const O& o, V ox, V oy, V oz, V dx, V dy, V dz, V cx, V cy,
                                              V cz, V r) {
    const V zero = o.k(0);
    const FF<V> fx = two_diff(o, ox, cx), fy = two_diff(o, oy, cy), fz = two_diff(o, oz, cz);
    // a = d.d and h = f.d, float-float (the lo parts of f enter as small terms).
    const FF<V> a = dot2(o, dx, dy, dz, dx, dy, dz);
    const V ninv_a = o.k(-1) / a.hi;    // off the discriminant's path: the divider starts on it at once
    FF<V> h = dot2(o, fx.hi, fy.hi, fz.hi, dx, dy, dz);
    h = renorm(o, h.hi, h.lo + (fx.lo * dx + fy.lo * dy + fz.lo * dz));
    // g = f x d, each component in float-float.
    const FF<V> gx = diff_of_products(o, fy.hi, dz, fz.hi, dy, fy.lo * dz - fz.lo * dy);
    const FF<V> gy = diff_of_products(o, fz.hi, dx, fx.hi, dz, fz.lo * dx - fx.lo * dz);
    const FF<V> gz = diff_of_products(o, fx.hi, dy, fy.hi, dx, fx.lo * dy - fy.lo * dx);
    // |g|^2 and a r^2 in float-float, then the discriminant.
    FF<V> g2 = dot2(o, gx.hi, gy.hi, gz.hi, gx.hi, gy.hi, gz.hi);
    g2.lo = g2.lo + o.k(2) * (gx.hi * gx.lo + gy.hi * gy.lo + gz.hi * gz.lo);
    const FF<V> r2 = two_prod(o, r, r);
    FF<V> ar2 = two_prod(o, a.hi, r2.hi);
    ar2.lo = ar2.lo + (a.hi * r2.lo + a.lo * r2.hi);
    const FF<V> dd = two_diff(o, ar2.hi, g2.hi);
    const FF<V> disc = renorm(o, dd.hi, dd.lo + (ar2.lo - g2.lo));
    const auto hit = o.ge(disc.hi, zero);
    // sqrt of the float-float discriminant: s, then one Newton step.
    const V dh = o.zero_unless(hit, disc.hi);
    V s = o.sqrt(dh);
    const V safe = o.select(o.gt(s, zero), s, o.k(1));
    s = s + o.zero_unless(o.gt(s, zero), (o.nfma(s, s, dh) + disc.lo) / (o.k(2) * safe));
    // p = h + sign(h) s = -q in float-float: the two terms have the same sign.
    const FF<V> ps = two_sum(o, h.hi, o.copysign(s, h.hi));
    const FF<V> p = renorm(o, ps.hi, ps.lo + h.lo);
    // c = |f|^2 - r^2 in float-float.
    FF<V> ff = dot2(o, fx.hi, fy.hi, fz.hi, fx.hi, fy.hi, fz.hi);
    ff.lo = ff.lo + o.k(2) * (fx.hi * fx.lo + fy.hi * fy.lo + fz.hi * fz.lo);
    const FF<V> cc = two_diff(o, ff.hi, r2.hi);
    const FF<V> c = renorm(o, cc.hi, cc.lo + (ff.lo - r2.lo));
    // The roots are q / a = -(p / a) and c / q = -(c / p).
    const V u = minus_quotient(o, p.hi, p.lo, a.hi, a.lo, ninv_a);
    const V w = minus_quotient(o, c.hi, c.lo, p.hi, p.lo, o.k(-1) / p.hi);
    return {o.zero_unless(hit, o.min(u, w)), o.zero_unless(hit, o.max(u, w)), hit};
}

/// The operations a formulation needs, on one number of type T (float,
/// double or Counted<...>); B is the plain type inside.
template <class T, class B>
struct ScalarOps {
    using V = T;
    using M = bool;
    V k(double x) const { return V(static_cast<B>(x)); }
    V neg(V x) const { return -x; }
    V fma(V a, V b, V c) const { return fused(a, b, c); }
    V fms(V a, V b, V c) const { return fused(a, b, -c); }
    V nfms(V a, V b, V c) const { return fused(-a, b, -c); }
    V nfma(V a, V b, V c) const { return fused(-a, b, c); }
    V sqrt(V x) const { using std::sqrt; return sqrt(x); }
    V copysign(V mag, V sign) const { using std::copysign; return copysign(mag, sign); }
    V min(V a, V b) const { return b < a ? b : a; }
    V max(V a, V b) const { return a < b ? b : a; }
    M ge(V a, V b) const { return a >= b; }
    M gt(V a, V b) const { return a > b; }
    V select(M m, V a, V b) const { return m ? a : b; }
    V zero_unless(M m, V a) const { return m ? a : k(0); }
};
