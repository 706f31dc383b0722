// The visible tiers' rules, as yes/no answers, so that a hidden family can stop at
// its first failing draw and report only that one (in the visible tier's words).
#pragma once

#include <optional>

#include "../support/grading.hpp"

namespace raykit::hidden {

// The basic tier's yes/no rules (agree, first_in_window) live in grading.hpp, where the visible
// window-end cases use them too.
using grading::agree;
using grading::first_in_window;

/// Whether `got` is a right answer for the window, judged without a knife's edge. Right is the
/// reference's answer; and, where the code's own roots (`own`) agree with the reference's within
/// the basic tolerance, also the smallest of its own roots inside the window. A root the basic tier
/// accepts can be a few ulps off, so where the exact root sits on a window end (a ray starting on
/// the sphere, a window cut at a root) it may land on either side of it: both answers are right.
/// An open window is still caught: with its own roots exactly at the end, the code must return it.
/// `own` is called only when the first answer disagrees.
template <class OwnRoots>
bool agree_in_window(const std::optional<float>& expected, const std::optional<float>& got,
                     const Roots& reference_roots, OwnRoots own, float tmin, float tmax) {
    if (agree(expected, got)) return true;
    Roots mine;
    try {
        mine = own();
    } catch (...) {
        return false;   // its own roots cannot be had: the reference's answer is the only right one
    }
    return agree(reference_roots, mine) && agree(first_in_window(mine, tmin, tmax), got);
}

}  // namespace raykit::hidden

// ---- inputs shared by the hidden families of steps 01-03 ---------------------------

#include "hidden.hpp"

namespace raykit::hidden {

/// A ray whose origin lies exactly on the sphere (centre, r): the centre plus or minus r
/// along one axis (exact in float for small integer centres and radii, so c = f.f - r^2 is
/// exactly 0). kind 0: a direction perpendicular to that axis (h = 0 exactly, a tangent
/// at t = 0, where the root pair q/a, c/q has q = 0); kind 1: heading in (roots 0 and
/// -2h/a > 0); kind 2: heading out (roots -2h/a < 0 and 0). Small integer components,
/// scaled by 1 or 2, or normalized when `unit`, keep the far root below 7, so that any
/// correct float formula lands within the basic tolerance of the root 0.
inline Ray surface_ray(Draw& d, const glm::vec3& centre, float r, int kind, bool unit) {
    const int axis = d.integer(0, 2);
    const float s = d.sign();
    float p = 0, q = 0;
    while (p == 0 && q == 0) p = static_cast<float>(d.integer(-3, 3)), q = static_cast<float>(d.integer(-3, 3));
    const float m = kind == 0 ? 0.0f : static_cast<float>(d.integer(1, 3)) * (kind == 1 ? -s : s);
    glm::vec3 dir = d.permute({m, p, q}, axis);
    dir = unit ? glm::normalize(dir) : d.power_of_two(0, 1) * dir;
    return {centre + d.permute({s * r, 0, 0}, axis), dir};
}

}  // namespace raykit::hidden

namespace raykit::hidden {

/// A ray (and sphere) that the headers' contract rules say is a miss, `count == 0`: `ok`
/// with one value spoilt. kind 0: a NaN, kind 1: +inf or -inf, in a random component of
/// the origin, the direction or (when `centre` is given) the sphere's centre; kind 2 (only
/// when `overflow`): the direction, made unit, scaled by 2^k so that d.d overflows float
/// (|d| from 1e20 to 1e30) or underflows to 0 in float (|d| from 1e-30 to 1e-23) while every
/// component stays a finite float: the headers allow a miss or the true roots there.
/// Returns that k (0 for kinds 0 and 1): the true roots are those of the direction divided
/// by 2^k (scaled_roots). Without `infinite_direction` (step 03, whose precondition is a
/// unit direction) an infinity goes into a position only.
inline int spoil(Draw& d, Ray& ray, glm::vec3* centre, int kind, bool overflow, bool infinite_direction = true) {
    if (kind == 2 && overflow) {
        const int k = d.coin() ? d.integer(67, 99) : -d.integer(76, 100);
        ray.direction = std::ldexp(1.0f, k) * glm::normalize(ray.direction);
        return k;
    }
    const float bad = kind == 0 ? std::numeric_limits<float>::quiet_NaN()
                                : d.sign() * std::numeric_limits<float>::infinity();
    int where = d.integer(0, centre ? 2 : 1);
    if (where == 1 && kind == 1 && !infinite_direction) where = 0;
    glm::vec3& v = where == 0 ? ray.origin : where == 1 ? ray.direction : *centre;
    v[d.integer(0, 2)] = bad;
    return 0;
}

/// `ray` with its direction divided by 2^k (exact: a power of two on a unit direction).
inline Ray unscaled(const Ray& ray, int k) { return {ray.origin, std::ldexp(1.0f, -k) * ray.direction}; }

/// The roots `r` of a ray whose direction is then multiplied by 2^k: each root divided by 2^k,
/// exactly (they stay normal floats for the k spoil draws).
inline Roots scaled_roots(Roots r, int k) {
    for (float& t : r.t) t = std::ldexp(t, -k);
    return r;
}

/// The headers' rule for a direction whose d.d overflows or underflows float (steps 01 and 02
/// alike): count 0, or the true roots, computed in a wider type. Never NaN.
inline bool agree_miss_or_true(const Roots& truth, const Roots& got) {
    return got.count == 0 || agree(truth, got);
}

/// A ray well through the sphere (centre `c`, radius `r`) whose direction is tiny: length 2^-k for
/// k from 20 to 56 (about 1e-6 down to 1.4e-17, shorter than FLT_EPSILON from k = 24, and d.d
/// still a normal float), so the roots are asked for. Half of them lie in a coordinate plane
/// through the centre, and the direction's third component, 0 there, becomes a subnormal number
/// (1e-39 to 1e-45): it moves nothing a float can show. Scaling by a power of two is exact, so
/// every float formula's answer is its answer for a direction of length 1, scaled.
inline Ray tiny_ray(Draw& d, const glm::vec3& c, float r) {
    const bool subnormal = d.coin();
    const int j = d.integer(0, 2);
    glm::vec3 out = d.direction(), off = d.direction();
    if (subnormal) {
        out[j] = off[j] = 0;
        if (glm::dot(out, out) < 0.1f) out = d.permute({1, 0, 0}, (j + 1) % 3);
        out = glm::normalize(out);
    }
    Ray ray = aimed(c + d.uniform(1.5f * r, 8 * r) * out, c + d.uniform(0, 0.7f * r) * off, 1);
    ray.direction *= d.power_of_two(-56, -20);
    if (subnormal) ray.direction[j] = d.sign() * std::ldexp(d.uniform(1, 2), -d.integer(128, 148));
    return ray;
}

}  // namespace raykit::hidden
