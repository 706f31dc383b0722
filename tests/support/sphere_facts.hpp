// More facts measured on the student's own sphere functions (issue 54, from trial 8's unplanted slips:
// docs/trials/trial8.md), beside relations.hpp's:
//   - a windowed answer lies inside its window: a t outside [tmin, tmax] is a fact about the answer alone
//     (window_outside_cause);
//   - renaming the axes leaves the roots unchanged: the same ray and sphere with (x, y, z) taken as
//     (y, z, x) (or (z, x, y)) must give the same roots, so code right there and wrong here reads a
//     component from the wrong axis (axes_cause);
//   - a radius that is not a whole number: roots that are exactly those of the radius without its
//     fraction say that the radius went through an int (int_radius_cause);
//   - the quadratic's a is d.d: on probe rays of the kit's own along a line through the centre, right
//     where |o - c| = |d| and those of a = f.f elsewhere (a_from_f_cause);
//   - the stable pair (q / a, c / q): a NaN beside a 0 from q = 0 (zero_over_q_cause), q / c for c / q
//     (q_over_c_cause), the discriminant's 4 (stable_4ac_cause);
//   - one root wrong and both right with d of length 1: a = d.d divides only part of it (precedence,
//     one_root_undivided_cause).
// Unlike relations.hpp's facts, which follow check_roots's sentence on the contract, these lead the
// message (check_roots_led): where they are measured, the count or the value being wrong is their
// consequence, and a sentence about the contract read first ("the discriminant is exactly 0 here")
// would point at a test that is right.
#pragma once

#include <cmath>
#include <optional>
#include <utility>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>
#include <string>

#include "grading.hpp"
#include "relations.hpp"

namespace raykit::grading {

/// A windowed answer outside its own window: `got` is a t with tmin <= t <= tmax false (NaN aside, a
/// message of its own). Empty otherwise. Measured on the answer alone: no call is made.
inline std::string window_outside_cause(float tmin, float tmax, const std::optional<float>& expected,
                                        const std::optional<float>& got) {
    if (!got || std::isnan(*got) || agree(expected, got) || !(tmin <= tmax)) return "";
    if (tmin <= *got && *got <= tmax) return "";
    return " Measured on your answer: your root t = " + show(*got) + " lies outside the window [" + show(tmin) +
           ", " + show(tmax) + "]. Return a root only when tmin <= t and t <= tmax both hold for that same root "
           "(tmin <= r.t[k] && r.t[k] <= tmax, the same k in both tests).";
}

/// The axes renamed once (k = 1: (x, y, z) -> (y, z, x)) or twice ((z, x, y)): exact, no arithmetic.
inline glm::vec3 axes_turned(const glm::vec3& v, int k) {
    return k == 1 ? glm::vec3(v.y, v.z, v.x) : k == 2 ? glm::vec3(v.z, v.x, v.y) : v;
}

/// Renaming the axes leaves every root unchanged: measured with `turned(k)`, the function asked with
/// the case's ray and sphere with their axes renamed k times (k = 1, 2). A function right there and
/// wrong here reads a component from the wrong axis. Empty when the answer is right, either renaming
/// gives the same wrong answer (a slip of another kind), or nothing is measured.
template <class Turned>
std::string axes_cause(const Roots& expected, const Roots& got, Turned turned) {
    if (agree(expected, got) || !cheap_to_measure()) return "";
    for (int k = 1; k <= 2; ++k)
        if (agree(expected, turned(k)))
            return std::string(" Measured on your function: the same ray and sphere with the axes renamed (x, y, z "
                               "read as ") + (k == 1 ? "y, z, x" : "z, x, y") +
                   ") give the right roots, and here they do not. A right formula treats x, y and z alike, so "
                   "your code reads a component from the wrong axis: check each x, y and z of o, d and c (a "
                   "copy-pasted dx where dz belongs in o.d, or d.z read from d.y).";
    return "";
}

/// The roots (sorted; one for a discriminant of 0) of the sphere of radius `r` for `ray`, in double
/// from the float inputs, by the half-b form (a = d.d, h = f.d, c = f.f - r^2). A discriminant within
/// rounding of 0 (1e-12 of h^2) is a tangent.
inline Roots roots_in_double(const Ray& ray, const glm::vec3& center, double r) {
    const double fx = double(ray.origin.x) - center.x, fy = double(ray.origin.y) - center.y,
                 fz = double(ray.origin.z) - center.z;
    const double dx = ray.direction.x, dy = ray.direction.y, dz = ray.direction.z;
    const double a = dx * dx + dy * dy + dz * dz, h = fx * dx + fy * dy + fz * dz,
                 c = fx * fx + fy * fy + fz * fz - r * r;
    Roots out;
    if (!(a > 0)) return out;
    const double disc = h * h - a * c;
    if (std::fabs(disc) <= 1e-12 * h * h) {
        out.count = 1;
        out.t[0] = out.t[1] = static_cast<float>(-h / a);
    } else if (disc > 0) {
        const double s = std::sqrt(disc);
        out.count = 2;
        out.t[0] = static_cast<float>((-h - s) / a);
        out.t[1] = static_cast<float>((-h + s) / a);
    }
    return out;
}

/// A radius that is not a whole number, and roots that are exactly those of the radius without its
/// fraction (rounded toward 0, as an int keeps it): the radius went through an int. Measured on the
/// answer alone. Empty otherwise.
inline std::string int_radius_cause(const Ray& ray, const Sphere& sphere, const Roots& expected, const Roots& got) {
    const float r = sphere.radius;
    if (agree(expected, got) || !std::isfinite(r) || !(r > 0) || r == std::trunc(r) || r > 1e6f) return "";
    const double whole = std::trunc(double(r));
    if (!agree(roots_in_double(ray, sphere.center, whole), got)) return "";
    return " Measured on your answer: your roots are those of a sphere of radius " + show(float(whole)) +
           ", the radius " + show(r) + " without its fraction. Is the radius kept in an int somewhere (int r = "
           "sphere.radius)? The fraction is lost there: keep it a float (or a double).";
}

/// The quadratic's a taken as f.f (f = o - c) where d.d belongs, measured on probe rays of the kit's own
/// (`roots_of(ray, sphere)`) around the sphere of radius 2 about (1, 2, 3), along +z through its centre:
/// from 1 below the centre (|f| = |d| = 1, where f.f = d.d and the slip is right: roots -1 and 3), and
/// from the surface, 2 below (right: 0 and 4; with a = f.f = 4: 4t^2 - 4t = 0, roots 0 and 1). Empty
/// unless the first is right and the second is exactly the slip's.
template <class RootsOf>
std::string a_from_f_cause(RootsOf roots_of) {
    if (!cheap_to_measure()) return "";
    const Sphere ball{{1, 2, 3}, 2};
    const Roots near = roots_of(Ray{ball.center + glm::vec3(0, 0, -1), {0, 0, 1}}, ball);
    if (!agree(Roots{2, {-1, 3}}, near)) return "";
    const Roots surface = roots_of(Ray{ball.center + glm::vec3(0, 0, -2), {0, 0, 1}}, ball);
    if (agree(Roots{2, {0, 4}}, surface) || !agree(Roots{2, {0, 1}}, surface)) return "";
    return " Measured on your function: on rays of the kit's own along a line through the centre, it is right "
           "where |o - c| = |d| and wrong elsewhere, where its roots are those of a = f.f (f = o - c): the "
           "quadratic's a is d.d, the direction's length squared, whatever the origin.";
}

/// The quadratic's numbers for `ray` and `sphere`, in double from the float inputs: a = d.d, h = f.d and
/// c = f.f - r^2 (f = o - c).
struct Quadratic {
    double a, h, c;
};

inline Quadratic quadratic_of(const Ray& ray, const Sphere& sphere) {
    const glm::dvec3 f = glm::dvec3(ray.origin) - glm::dvec3(sphere.center), d = glm::dvec3(ray.direction);
    const double r = sphere.radius;
    return {glm::dot(d, d), glm::dot(f, d), glm::dot(f, f) - r * r};
}

/// The stable pair's 0 / 0: a NaN beside a root of 0, where the discriminant is positive and c = 0 (the
/// origin on the surface). q = -(h + s) without h's sign is 0 there, so q/a is 0 and c/q is 0/0. Measured
/// on the answer and the case's own numbers. Empty otherwise.
inline std::string zero_over_q_cause(const Ray& ray, const Sphere& sphere, const Roots& expected, const Roots& got) {
    if (expected.count != 2 || got.count != 2 || !(expected.t[0] == 0 || expected.t[1] == 0)) return "";
    const bool nan0 = std::isnan(got.t[0]), nan1 = std::isnan(got.t[1]);
    if (nan0 == nan1 || (nan0 ? got.t[1] : got.t[0]) != 0.0f) return "";
    const Quadratic q = quadratic_of(ray, sphere);
    const double disc = q.h * q.h - q.a * q.c;
    if (!(disc > 0) || q.c != 0) return "";
    return " Measured on your answer: one root is 0 and the other NaN, where the discriminant h^2 - a c = " +
           show(float(disc)) + " is positive: this NaN is no square root of a negative number but 0 / 0, c / q "
           "with q = 0 (c = 0: the origin is on the sphere). In the stable pair q = -(h + s) when h >= 0 and "
           "-(h - s) when h < 0, so that h and s never cancel: take the branch on h's sign.";
}

/// The stable pair's second root written q / c where c / q belongs: one root right (t = q / a) and the
/// other exactly a t / c (that is q / c). Measured on the answer and the case's own numbers. Empty
/// otherwise.
inline std::string q_over_c_cause(const Ray& ray, const Sphere& sphere, const Roots& expected, const Roots& got) {
    if (expected.count != 2 || got.count != 2 || agree(expected, got) || has_nan(got)) return "";
    const Quadratic q = quadratic_of(ray, sphere);
    if (q.c == 0) return "";
    for (int i = 0; i < 2; ++i) {
        const int right = close(expected.t[0], got.t[i]) ? 0 : close(expected.t[1], got.t[i]) ? 1 : -1;
        if (right < 0) continue;
        const float other = got.t[1 - i], want = expected.t[1 - right];
        if (close(want, other) || !close(float(q.a * got.t[i] / q.c), other)) continue;
        return " Measured on your answer: your root " + show(got.t[i]) + " is right and the other, " + show(other) +
               ", is q / c (q = " + show(float(q.a * got.t[i])) + ", c = " + show(float(q.c)) + ") where c / q = " +
               show(want) + " belongs: the two roots multiply to c / a, so the second root of the stable pair is "
               "c / q, not q / c.";
    }
    return "";
}

/// The stable pair (q / a and c / q, q = -(h + sign(h) s)) with the discriminant h^2 - 4 a c where the half-b
/// form has h^2 - a c, measured on a probe ray of the kit's own that starts inside the sphere (`roots_of`,
/// as formula_cause asks: the unit sphere at the origin, or the sphere of radius 2 about (1, 2, 3)), r/2
/// behind the centre along +z. relations.hpp's formula_cause knows the textbook form's 4; this is the
/// stable pair's. Empty unless the answer is exactly that variation's.
template <class RootsOf>
std::string stable_4ac_cause(bool unit_sphere, RootsOf roots_of) {
    if (!cheap_to_measure()) return "";
    const Sphere ball = unit_sphere ? Sphere{{0, 0, 0}, 1} : Sphere{{1, 2, 3}, 2};
    const Ray inside{ball.center + glm::vec3(0, 0, -0.5f * ball.radius), {0, 0, 1}};
    const Quadratic q = quadratic_of(inside, ball);
    const double s = std::sqrt(q.h * q.h - 4 * q.a * q.c), big = q.h >= 0 ? -(q.h + s) : -(q.h - s);
    double t0 = big / q.a, t1 = q.c / big;
    if (t0 > t1) std::swap(t0, t1);
    const Roots got = roots_of(inside, ball);
    if (agree(pair_of(-0.5 * ball.radius, 1.5 * ball.radius), got) || !agree(pair_of(t0, t1), got)) return "";
    return " Measured on your function: asked about a ray of the kit's own that starts inside the sphere, it "
           "gives what the stable pair (q / a and c / q) gives with the discriminant h^2 - 4 a c: with h = b/2 "
           "(h = f.d) the discriminant is h^2 - a c; the 4 belongs to the whole b, b^2 - 4ac.";
}

/// Only one root wrong, and both right on the same line with d of length 1 (`unit_answer`, the function
/// asked with d / |d|): a = d.d divides only part of that root's formula (a = 1 hides it). Empty
/// otherwise, or when |d| is 1.
template <class UnitAnswer>
std::string one_root_undivided_cause(const glm::vec3& d, const Roots& expected, const Roots& got, UnitAnswer unit_answer) {
    if (expected.count != 2 || got.count != 2 || has_nan(got) || !cheap_to_measure()) return "";
    const float len = length_of(d);
    if (len == 0.0f || std::fabs(len - 1.0f) <= 1e-3f) return "";
    const bool ok0 = close(expected.t[0], got.t[0]) || close(expected.t[0], got.t[1]);
    const bool ok1 = close(expected.t[1], got.t[1]) || close(expected.t[1], got.t[0]);
    if (ok0 == ok1 || !agree(scaled(expected, len), unit_answer(1.0f / len))) return "";
    const float wrong = ok0 ? expected.t[1] : expected.t[0];
    return " Measured on your function: one root is right and the other is not (" + show(wrong) + " expected), "
           "and on the same line with d scaled to length 1 both are right: that root's formula divides only "
           "part of its numerator by a = d.d (at |d| = 1, a = 1 hides it). Put the whole numerator in "
           "parentheses: (-b -+ sqrt(b^2 - a c)) / a.";
}

/// check_roots with a leading fact: where `lead` is measured, it comes first and the case's geometry
/// (the why's first sentence) after it, before any sentence on the contract; otherwise check_roots with
/// `why` as it is.
inline void check_roots_led(const std::string& call, const std::string& input, const Roots& expected,
                            const Roots& got, const std::string& lead, const std::string& why) {
    if (lead.empty() || agree(expected, got)) return check_roots(call, input, expected, got, why);
    figure::note_failure(call, figure::json(expected), figure::json(got));
    FAIL_CHECK(report(call, input, show(expected), show(got), with_fact(lead, why)));
}

}  // namespace raykit::grading
