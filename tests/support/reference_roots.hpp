// The exact roots of a ray and a sphere, for grading and benchmarking.
//
// The robust cases compare a float answer with the root of the *same float
// inputs* computed in much higher precision, so that the only error measured
// is the one the float formula adds. Each input float is widened without loss;
// f = o - c, every product and the discriminant are then exact or within
// about 2^-113 of exact, far below the float rounding (2^-24) we grade.
//
// Wide type: __float128 where the compiler has it (GCC and Clang on x86-64),
// else long double (a 128-bit IEEE quad on AArch64). Only + - * / and
// comparisons are used, which the compiler's runtime provides; the square
// root is computed here by Newton's iteration, so no libquadmath is needed.
//
// No doctest here: the benchmark includes this file too.
#pragma once

#include <cmath>
#include <utility>

#include "raykit/ray.hpp"
#include "raykit/roots.hpp"
#include "raykit/sphere.hpp"

namespace raykit::reference {

#if defined(__SIZEOF_FLOAT128__)
__extension__ typedef __float128 wide;
#else
typedef long double wide;
#endif

/// Roots in the wide type; same contract as raykit::Roots.
struct WideRoots {
    int count = 0;
    wide t[2] = {0, 0};
};

/// Square root of x >= 0 in the wide type.
inline wide wide_sqrt(wide x) {
    if (!(x > 0)) return 0;
    // Bring x into double's comfortable range by an even power of two (exact),
    // take double's square root as the first guess (53 good bits), and let two
    // Newton steps y <- (y + x/y)/2 double the good bits twice: past 113.
    wide scale = 1;
    while (x > wide(0x1p+500)) {
        x *= wide(0x1p-500);
        scale *= wide(0x1p+250);
    }
    while (x < wide(0x1p-500)) {
        x *= wide(0x1p+500);
        scale *= wide(0x1p-250);
    }
    wide y = std::sqrt(static_cast<double>(x));
    y = (y + x / y) / 2;
    y = (y + x / y) / 2;
    return y * scale;
}

inline bool finite(const glm::vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

/// The roots of a t^2 + 2 h t + c = 0 in the wide type, from a discriminant already formed: none
/// when a <= 0 or disc < 0, one when disc == 0. Even here, take the sum that cannot cancel and get
/// the other root from the product of the roots (c / a).
inline WideRoots wide_pair(wide a, wide h, wide c, wide disc) {
    if (!(a > 0) || disc < 0) return {};
    WideRoots out;
    if (disc == 0) {
        out.count = 1;
        out.t[0] = out.t[1] = -h / a;
        return out;
    }
    const wide s = wide_sqrt(disc);
    const wide q = -(h + (h < 0 ? -s : s));
    wide t0 = q / a, t1 = c / q;
    if (t0 > t1) {
        const wide tmp = t0;
        t0 = t1;
        t1 = tmp;
    }
    out.count = 2;
    out.t[0] = t0;
    out.t[1] = t1;
    return out;
}

/// Wide roots rounded to the nearest floats.
inline Roots rounded(const WideRoots& w) {
    Roots out;
    out.count = w.count;
    for (int i = 0; i < w.count; ++i) out.t[i] = static_cast<float>(w.t[i]);
    if (w.count == 1) out.t[1] = out.t[0];
    return out;
}

/// The roots of |o + t d - c|^2 = r^2 from the float inputs, in the wide type.
///
/// No roots for a zero direction, a radius that is not a positive finite
/// number, or a non-finite input; one root when the discriminant is exactly
/// zero (a tangent) for these inputs.
inline WideRoots sphere_roots_wide(const Ray& ray, const Sphere& sphere) {
    if (!(sphere.radius > 0.0f) || !std::isfinite(sphere.radius)) return {};
    if (!finite(ray.origin) || !finite(ray.direction) || !finite(sphere.center)) return {};
    wide f[3], d[3];
    for (int i = 0; i < 3; ++i) {
        f[i] = wide(ray.origin[i]) - wide(sphere.center[i]);
        d[i] = wide(ray.direction[i]);
    }
    const wide r = sphere.radius;
    const wide a = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    const wide h = f[0] * d[0] + f[1] * d[1] + f[2] * d[2];
    const wide c = f[0] * f[0] + f[1] * f[1] + f[2] * f[2] - r * r;
    return wide_pair(a, h, c, h * h - a * c);
}

/// sphere_roots_wide() rounded to the nearest floats: the best answer a float
/// function can give.
inline Roots sphere_roots_rounded(const Ray& ray, const Sphere& sphere) {
    return rounded(sphere_roots_wide(ray, sphere));
}

// --- Suspects: what the usual wrong formulas give on the same inputs ----------------
//
// When a ★ answer fails, the grader names the cause the answer matches, measured, not assumed
// (tests/support/robust_grading.hpp, measured_cause). These are the candidates, each the exact
// computation with one known flaw, so that a match names that flaw alone:
//  - a_one: the roots of t^2 + 2 h t + c' = 0, exact: the formula that takes a = d.d as 1;
//  - float_cprime: exact, except that f = o - c and c' = f.f - r^2 are computed in float;
//  - textbook_float: the textbook formula with every operation rounded to float;
//  - shortcut_float: the unit-direction shortcut -h -+ sqrt(h^2 - c') (a taken as 1), in float;
//  - textbook_double: the textbook formula with every operation in double, from the float inputs (the
//    roots rounded to float last), the form tests/fixtures/forms/double_inside/ computes: where even a
//    double cannot hold h^2 - a c' (pbrt's test ranges), a failure in double is named for what it is.
// They are recorded with the exact roots (./kit exact --refresh), so a handout carries only their
// values on the graded inputs, never the code.

// One float operation, rounded to float and never fused with the next (the volatile store forces the
// rounding whatever the compiler's contraction rules), so the recorded values do not depend on the
// machine that records them.
inline float fl(float x) {
    volatile float v = x;
    return v;
}
inline float fl_dot(const float* x, const float* y) {
    return fl(fl(fl(x[0] * y[0]) + fl(x[1] * y[1])) + fl(x[2] * y[2]));
}

struct SuspectRoots {
    Roots a_one, float_cprime, textbook_float, shortcut_float, textbook_double;
};

// The same in double: one operation, rounded to double and never fused with the next.
inline double dl(double x) {
    volatile double v = x;
    return v;
}
inline double dl_dot(const double* x, const double* y) {
    return dl(dl(dl(x[0] * y[0]) + dl(x[1] * y[1])) + dl(x[2] * y[2]));
}

/// -h -+ sqrt(disc), over a, with every operation in double, each root rounded to float last; the
/// contract's count and order.
inline Roots double_pair(double a, double h, double disc) {
    Roots t;
    if (!(a > 0.0) || !std::isfinite(a) || !std::isfinite(disc) || !(disc >= 0.0)) return t;
    if (disc == 0.0) {
        const float root = static_cast<float>(dl(-h / a));
        return {1, {root, root}};
    }
    const double s = dl(std::sqrt(disc));
    float t0 = static_cast<float>(dl(dl(-h - s) / a)), t1 = static_cast<float>(dl(dl(-h + s) / a));
    if (t0 > t1) std::swap(t0, t1);
    if (std::isnan(t0) || std::isnan(t1)) return {};
    return {2, {t0, t1}};
}

/// -h -+ sqrt(disc), over a, with every operation in float; the contract's count and order.
inline Roots float_pair(float a, float h, float disc) {
    Roots t;
    if (!(a > 0.0f) || !std::isfinite(disc) || !(disc >= 0.0f)) return t;
    if (disc == 0.0f) return {1, {fl(-h / a), fl(-h / a)}};
    const float s = fl(std::sqrt(disc));
    float t0 = fl(fl(-h - s) / a), t1 = fl(fl(-h + s) / a);
    if (t0 > t1) std::swap(t0, t1);
    if (std::isnan(t0) || std::isnan(t1)) return {};
    return {2, {t0, t1}};
}

inline SuspectRoots suspect_roots(const Ray& ray, const Sphere& sphere) {
    SuspectRoots out;
    if (!(sphere.radius > 0.0f) || !std::isfinite(sphere.radius)) return out;
    if (!finite(ray.origin) || !finite(ray.direction) || !finite(sphere.center)) return out;
    const float r = sphere.radius;
    float ff[3], fd[3];
    wide f[3], d[3], g[3];
    for (int i = 0; i < 3; ++i) {
        f[i] = wide(ray.origin[i]) - wide(sphere.center[i]);
        d[i] = wide(ray.direction[i]);
        fd[i] = ray.direction[i];
        ff[i] = fl(ray.origin[i] - sphere.center[i]);
        g[i] = wide(ff[i]);
    }
    // a = 1: h and c' exact, the discriminant h^2 - c'.
    {
        const wide h = f[0] * d[0] + f[1] * d[1] + f[2] * d[2];
        const wide c = f[0] * f[0] + f[1] * f[1] + f[2] * f[2] - wide(r) * wide(r);
        out.a_one = rounded(wide_pair(1, h, c, h * h - c));
    }
    // c' in float: f and c' as float computes them, the rest exact.
    const float cf = fl(fl_dot(ff, ff) - fl(r * r));
    {
        const wide a = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        const wide h = g[0] * d[0] + g[1] * d[1] + g[2] * d[2];
        out.float_cprime = rounded(wide_pair(a, h, wide(cf), h * h - a * wide(cf)));
    }
    // The textbook formula in float: -h -+ sqrt(h^2 - a c'), over a (h is half of b: b^2 - 4ac is
    // 4 (h^2 - a c') exactly in binary, so the b form rounds to the same numbers); and the shortcut,
    // the same with a taken as 1.
    const float a = fl_dot(fd, fd), h = fl_dot(ff, fd);
    out.textbook_float = float_pair(a, h, fl(fl(h * h) - fl(a * cf)));
    out.shortcut_float = float_pair(1.0f, h, fl(fl(h * h) - cf));
    // The textbook formula in double: f = o - c, a, h and c' = f.f - r^2 each rounded to double, then the
    // discriminant h^2 - a c' and the roots (b = 2h and b^2 - 4ac round to the same numbers, as in float).
    {
        double df[3], dd[3];
        for (int i = 0; i < 3; ++i) {
            df[i] = dl(double(ray.origin[i]) - double(sphere.center[i]));
            dd[i] = double(ray.direction[i]);
        }
        const double da = dl_dot(dd, dd), dh = dl_dot(df, dd);
        const double dc = dl(dl_dot(df, df) - dl(double(r) * double(r)));
        out.textbook_double = double_pair(da, dh, dl(dl(dh * dh) - dl(da * dc)));
    }
    return out;
}

}  // namespace raykit::reference
