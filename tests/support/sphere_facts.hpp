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
//     where |o - c| = |d| and those of a = f.f elsewhere (a_from_f_cause).
// Unlike relations.hpp's facts, which follow check_roots's sentence on the contract, these lead the
// message (check_roots_led): where they are measured, the count or the value being wrong is their
// consequence, and a sentence about the contract read first ("the discriminant is exactly 0 here")
// would point at a test that is right.
#pragma once

#include <cmath>
#include <optional>
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
