// The ray-sphere formulations the benchmark compares.
//
// Each one finds where the whole line o + t d meets the sphere |x - c| = r,
// t counting multiples of d (d need not be unit length), and returns both
// roots sorted or a miss. They are written for the benchmark, one short
// template each, so they run in float, in double and in Counted<T> (which
// counts their flops). Every variant reads the same inputs; only the algebra
// differs. The names follow the lecture:
//
//   textbook     a t^2 + b t + c = 0 and the school formula
//   half_b       the same with b = 2h, which saves a few multiplies
//   unit_dir     normalise d first, so a = 1
//   geometric    project the centre on the ray, then Pythagoras
//   stable       the discriminant as r^2 - (distance of the line)^2 and the
//                root pair that never subtracts nearly equal numbers
//   lagrange     the discriminant by Lagrange's identity, a r^2 - |f x d|^2:
//                the squared distance of the line read as a cross product
//   in_double    any of them on float inputs, computed in double, rounded to float
//
// For the stable form see E. Haines, J. Guenther and T. Akenine-Moller,
// "Precision Improvements for Ray/Sphere Intersection", Ray Tracing Gems,
// 2019, ch. 7; the root pair is the classic one from numerical analysis
// (e.g. Press et al., Numerical Recipes, "Quadratic and Cubic Equations").
//
// What none of them guards against: a zero direction (the benchmark's rays
// never have one) and the exact tangent (measure zero; reported as a hit with
// two equal roots). The kit's reference solutions do handle both.
#pragma once

#include <cmath>
#include <utility>

#include "vec.hpp"

namespace raykit::bench {

// Each variant is exactly one out-of-line call per ray (variants.cpp); the
// formulation is inlined into it whatever the compiler's size heuristics say,
// so no variant pays for a second call the others do not.
#define RAYKIT_FORMULATION __attribute__((always_inline)) inline

/// a t^2 + b t + c = 0 with a = d.d, b = 2 f.d, c = f.f - r^2, f = o - c, and
/// t = (-b -+ sqrt(b^2 - 4ac)) / 2a. Two cancellations: b^2 - 4ac when the
/// sphere is far (both terms ~ |f|^2 |d|^2), and -b + sqrt(...) for the root
/// near zero (the origin close to the surface).
template <class T>
RAYKIT_FORMULATION RootsOf<T> textbook(const Sample<T>& s) {
    using std::sqrt;
    const Vec3<T> f = s.o - s.c;
    const T a = dot(s.d, s.d);
    const T b = T(2) * dot(f, s.d);
    const T c = dot(f, f) - s.r * s.r;
    const T disc = b * b - T(4) * a * c;
    if (!(disc >= T(0))) return {};  // also a miss for NaN
    const T root = sqrt(disc);
    const T two_a = T(2) * a;
    return {2, {(-b - root) / two_a, (-b + root) / two_a}};
}

/// The textbook form with b = 2h, h = f.d: the 2s and 4 cancel, leaving
/// t = (-h -+ sqrt(h^2 - ac)) / a. Fewer operations, the same cancellations.
template <class T>
RAYKIT_FORMULATION RootsOf<T> half_b(const Sample<T>& s) {
    using std::sqrt;
    const Vec3<T> f = s.o - s.c;
    const T a = dot(s.d, s.d);
    const T h = dot(f, s.d);
    const T c = dot(f, f) - s.r * s.r;
    const T disc = h * h - a * c;
    if (!(disc >= T(0))) return {};
    const T root = sqrt(disc);
    return {2, {(-h - root) / a, (-h + root) / a}};
}

/// Normalise the direction first: with u = d/|d| the quadratic has a = 1 and
/// t_u = -h -+ sqrt(h^2 - c), h = f.u. The roots are in units of u, so divide
/// by |d| to count multiples of d again. Costs a square root and a divide more;
/// the cancellations stay.
template <class T>
RAYKIT_FORMULATION RootsOf<T> unit_dir(const Sample<T>& s) {
    using std::sqrt;
    const T len = sqrt(dot(s.d, s.d));
    const Vec3<T> u = (T(1) / len) * s.d;
    const Vec3<T> f = s.o - s.c;
    const T h = dot(f, u);
    const T c = dot(f, f) - s.r * s.r;
    const T disc = h * h - c;
    if (!(disc >= T(0))) return {};
    const T root = sqrt(disc);
    return {2, {(-h - root) / len, (-h + root) / len}};
}

/// The geometric method: t_ca = (c - o).u is where the ray passes closest to
/// the centre, d^2 = |c - o|^2 - t_ca^2 the squared distance it passes at, and
/// the hits are t_ca -+ sqrt(r^2 - d^2) along u. d^2 is again a difference of
/// two large, nearly equal numbers when the sphere is far away.
template <class T>
RAYKIT_FORMULATION RootsOf<T> geometric(const Sample<T>& s) {
    using std::sqrt;
    const T len = sqrt(dot(s.d, s.d));
    const Vec3<T> u = (T(1) / len) * s.d;
    const Vec3<T> to_centre = s.c - s.o;
    const T t_ca = dot(to_centre, u);
    const T dist2 = dot(to_centre, to_centre) - t_ca * t_ca;
    const T r2 = s.r * s.r;
    if (!(dist2 <= r2)) return {};
    const T half_chord = sqrt(r2 - dist2);
    return {2, {(t_ca - half_chord) / len, (t_ca + half_chord) / len}};
}

/// Cancellation-free discriminant and stable root pair. The quarter
/// discriminant h^2 - ac equals a (r^2 - |l|^2), l = f - (h/a) d the vector
/// from the centre to the line's closest point: r^2 - |l|^2 only cancels
/// near a tangent, where the answer is ill-conditioned anyway. Then
/// q = -(h + sign(h) sqrt(disc)) adds two numbers of the same sign, and the
/// roots are q/a and c/q (their product is c/a).
template <class T>
RAYKIT_FORMULATION RootsOf<T> stable(const Sample<T>& s) {
    using std::copysign;
    using std::sqrt;
    const Vec3<T> f = s.o - s.c;
    const T a = dot(s.d, s.d);
    const T h = dot(f, s.d);
    const T r2 = s.r * s.r;
    const T c = dot(f, f) - r2;
    const Vec3<T> l = f - (h / a) * s.d;
    const T disc = a * (r2 - dot(l, l));
    if (!(disc >= T(0))) return {};
    const T q = -(h + copysign(sqrt(disc), h));
    T t0 = q / a;
    T t1 = c / q;
    if (t1 < t0) std::swap(t0, t1);
    return {2, {t0, t1}};
}

/// The discriminant by Lagrange's identity: (f.d)^2 - (d.d)(f.f) = -|f x d|^2,
/// so h^2 - ac = a r^2 - |f x d|^2. |f x d| / |d| is the distance of the line
/// from the centre: this is the stable form's discriminant without the
/// closest-point vector and without c. In double on float inputs each
/// component of f x d is one rounding (a product of two floats is exact in
/// double), so the discriminant cancels only near a tangent, whatever the
/// scale: this is the kit's reference (step 02), computed in double.
template <class T>
RAYKIT_FORMULATION RootsOf<T> lagrange(const Sample<T>& s) {
    using std::sqrt;
    const Vec3<T> f = s.o - s.c;
    const T a = dot(s.d, s.d);
    const T h = dot(f, s.d);
    const Vec3<T> g = cross(f, s.d);
    const T disc = a * (s.r * s.r) - dot(g, g);
    if (!(disc >= T(0))) return {};
    const T root = sqrt(disc);
    return {2, {(-h - root) / a, (-h + root) / a}};
}

/// The half-b discriminant h^2 - ac with the stable root pair q/a, c/q: the
/// kit's reference for step 02 computes this in double (see in_double). In
/// double, h^2 - ac no longer loses float precision for the families here, so
/// only the root pair, which guards a tiny root beside a large one, is kept.
template <class T>
RAYKIT_FORMULATION RootsOf<T> half_b_pair(const Sample<T>& s) {
    using std::copysign;
    using std::sqrt;
    const Vec3<T> f = s.o - s.c;
    const T a = dot(s.d, s.d);
    const T h = dot(f, s.d);
    const T c = dot(f, f) - s.r * s.r;
    const T disc = h * h - a * c;
    if (!(disc >= T(0))) return {};
    const T q = -(h + copysign(sqrt(disc), h));
    const T t0 = q / a;
    const T t1 = c / q;
    return {2, {t0 < t1 ? t0 : t1, t0 < t1 ? t1 : t0}};
}

/// Float in, float out, arithmetic in double: formulation F on the inputs
/// widened to double (exactly: every float is a double), its roots rounded
/// back to float once at the end. What "just use double inside" costs and buys
/// in a float ray tracer.
template <RootsOf<double> (*F)(const Sample<double>&)>
RAYKIT_FORMULATION RootsOf<float> in_double(const Sample<float>& s) {
    const RootsOf<double> r = F(convert<double>(s));
    return {r.count, {static_cast<float>(r.t[0]), static_cast<float>(r.t[1])}};
}

}  // namespace raykit::bench
