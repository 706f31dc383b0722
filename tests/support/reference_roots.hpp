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
    if (!(a > 0)) return {};
    const wide disc = h * h - a * c;
    if (disc < 0) return {};
    WideRoots out;
    if (disc == 0) {
        out.count = 1;
        out.t[0] = out.t[1] = -h / a;
        return out;
    }
    // Even here, take the sum that cannot cancel and get the other root from
    // the product of the roots (c / a).
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

/// sphere_roots_wide() rounded to the nearest floats: the best answer a float
/// function can give.
inline Roots sphere_roots_rounded(const Ray& ray, const Sphere& sphere) {
    const WideRoots w = sphere_roots_wide(ray, sphere);
    Roots out;
    out.count = w.count;
    for (int i = 0; i < w.count; ++i) out.t[i] = static_cast<float>(w.t[i]);
    if (w.count == 1) out.t[1] = out.t[0];
    return out;
}

}  // namespace raykit::reference
