// More facts measured on the student's own sphere functions (issue 54, from trial 8's unplanted slips:
// docs/trials/trial8.md), beside relations.hpp's:
//   - a windowed answer lies inside its window: a t outside [tmin, tmax] is a fact about the answer alone
//     (window_outside_cause);
//   - renaming the axes leaves the roots unchanged: the same ray and sphere with (x, y, z) taken as
//     (y, z, x) (or (z, x, y)) must give the same roots, so code right there and wrong here reads a
//     component from the wrong axis (axes_cause);
//   - a radius that is not a whole number: roots that stay the same when only its fraction changes say
//     that the radius went through an int (int_radius_cause);
//   - the quadratic's a is d.d: on probe rays of the kit's own along a line through the centre, right
//     where |o - c| = |d| and those of a = f.f elsewhere (a_from_f_cause);
//   - the stable pair of roots: a NaN beside a 0 from its larger term cancelling (zero_over_q_cause), the
//     second root divided the wrong way round (q_over_c_cause), the discriminant's 4 (stable_4ac_cause);
//   - one root wrong and both right with d of length 1: a = d.d divides only part of it (precedence,
//     one_root_undivided_cause).
// Unlike relations.hpp's facts, which follow check_roots's sentence on the contract, these lead the
// message (check_roots_led): where they are measured, the count or the value being wrong is their
// consequence, and a sentence about the contract read first ("the discriminant is exactly 0 here")
// would point at a test that is right.
#pragma once

#include <cmath>
#include <optional>
#include <string>

#include <glm/vec3.hpp>

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

/// A radius that is not a whole number, and an answer that keeps only its whole part: the same roots
/// with the radius's fraction changed (to .25 and .75: `with_radius(r)`, the function asked with the
/// case's sphere of radius r), and other roots with the whole part one more. A right answer changes with
/// any radius (the roots are wrong here, so the ray is no tangent of both); the radius went through an
/// int. Empty otherwise (an answer that ignores the radius altogether is the same at every radius).
template <class WithRadius>
std::string int_radius_cause(float radius, const Roots& expected, const Roots& got, WithRadius with_radius) {
    if (agree(expected, got) || has_nan(got) || !std::isfinite(radius) || !(radius > 0) ||
        radius == std::trunc(radius) || radius > 1e6f || !cheap_to_measure())
        return "";
    const float whole = std::trunc(radius);
    const Roots quarter = with_radius(whole + 0.25f), three_quarters = with_radius(whole + 0.75f),
                next = with_radius(whole + 1.25f);
    if (!same_answer(got, quarter) || !same_answer(got, three_quarters) || same_answer(got, next)) return "";
    return " Measured on your function: your roots are the same for a radius of " + show(whole + 0.25f) + ", " +
           show(radius) + " and " + show(whole + 0.75f) + ", and change at " + show(whole + 1.25f) +
           ": only the radius's whole part counts, its fraction is lost. Is the radius kept in an int somewhere "
           "(int r = sphere.radius)? Keep it a float (or a double).";
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
           "where the origin is as far from the centre as d is long, and wrong elsewhere, where its roots are those "
           "of a quadratic whose a is f.f (f = o - c): the quadratic's a is d.d, the direction's length squared, "
           "whatever the origin.";
}

/// The stable pair's 0 / 0: a NaN beside a root of 0, where two roots are expected and one of them is 0
/// (a positive discriminant, and the origin on the sphere). The pair's larger term without h's sign
/// cancels to 0 there, and the other root, divided by it, is 0 / 0. Measured on the answer. Empty otherwise.
inline std::string zero_over_q_cause(const Roots& expected, const Roots& got) {
    if (expected.count != 2 || got.count != 2 || !(expected.t[0] == 0 || expected.t[1] == 0)) return "";
    const bool nan0 = std::isnan(got.t[0]), nan1 = std::isnan(got.t[1]);
    if (nan0 == nan1 || (nan0 ? got.t[1] : got.t[0]) != 0.0f) return "";
    return " Measured on your answer: one root is 0 and the other NaN, where the roots are " + show(expected.t[0]) +
           " and " + show(expected.t[1]) + ": two roots, so the discriminant is positive, and this NaN is no square "
           "root of a negative number but 0 / 0. The origin is on the sphere (c = 0), and the stable pair's "
           "larger term, -(h + s), cancels to 0 here where h < 0: the sign in front of s must follow h's, so "
           "that h and s never cancel.";
}

/// The stable pair's second root divided the wrong way round: one root right, and the other exactly that
/// root divided by the product of the expected roots (which is c / a): the first root over c where c over
/// it belongs. Measured on the answer. Empty otherwise.
inline std::string q_over_c_cause(const Roots& expected, const Roots& got) {
    if (expected.count != 2 || got.count != 2 || agree(expected, got) || has_nan(got)) return "";
    const float product = expected.t[0] * expected.t[1];
    if (product == 0 || !std::isfinite(product)) return "";
    for (int i = 0; i < 2; ++i) {
        const int right = close(expected.t[0], got.t[i]) ? 0 : close(expected.t[1], got.t[i]) ? 1 : -1;
        if (right < 0) continue;
        const float other = got.t[1 - i], want = expected.t[1 - right];
        if (close(want, other) || !close(got.t[i] / product, other)) continue;
        return " Measured on your answer: your root " + show(got.t[i]) + " is right and the other, " + show(other) +
               ", is " + show(got.t[i]) + " / " + show(product) + ", where the two roots multiply to c / a = " +
               show(product) + " and the other root is " + show(product) + " / " + show(got.t[i]) + " = " +
               show(want) + ": your second root divides the other way round (the right root over c, where c "
               "over it belongs).";
    }
    return "";
}

/// The stable pair with the discriminant h^2 - 4 a c where the half-b form has h^2 - a c, measured on a
/// probe ray of the kit's own that starts inside the sphere (`roots_of`, as formula_cause asks: the unit
/// sphere at the origin, or the sphere of radius 2 about (1, 2, 3)), r/2 behind the centre along +z
/// (a = 1, h = -r/2, c = -3r^2/4). That variation's roots, worked out by hand: the larger term
/// r/2 + sqrt(13) r/2 = 2.3027756 r, and the other root -0.75 r^2 over it, -0.3256939 r. relations.hpp's
/// formula_cause knows the textbook form's 4; this is the stable pair's. Empty unless the answer is
/// exactly that variation's.
template <class RootsOf>
std::string stable_4ac_cause(bool unit_sphere, RootsOf roots_of) {
    if (!cheap_to_measure()) return "";
    const Sphere ball = unit_sphere ? Sphere{{0, 0, 0}, 1} : Sphere{{1, 2, 3}, 2};
    const double r = ball.radius;
    const Roots got = roots_of(Ray{ball.center + glm::vec3(0, 0, -0.5f * ball.radius), {0, 0, 1}}, ball);
    if (agree(pair_of(-0.5 * r, 1.5 * r), got) || !agree(pair_of(-0.3256939 * r, 2.3027756 * r), got)) return "";
    return " Measured on your function: asked about a ray of the kit's own that starts inside the sphere, it "
           "gives what the stable pair of roots gives with the discriminant h^2 - 4 a c: with h = b/2 (h = f.d) "
           "the discriminant is h^2 - a c; the 4 belongs to the whole b, b^2 - 4ac.";
}

/// Only one root wrong, and both right on the same line with d of length 1 (`unit_answer`, the function
/// asked with d / |d|): a = d.d divides only part of that root's formula (a = 1 hides it). Empty
/// otherwise, or when |d| is 1.
template <class UnitAnswer>
std::string one_root_undivided_cause(const glm::vec3& d, const Roots& expected, const Roots& got, UnitAnswer unit_answer) {
    if (expected.count != 2 || got.count != 2 || has_nan(got) || !cheap_to_measure()) return "";
    const float len = length_of(d);
    if (len == 0.0f || std::fabs(len - 1.0f) <= 1e-3f) return "";
    // Root by root, in order (a root equal to the other expected one proves nothing: a distance t |d| for
    // |d| = 2 gives 2 and 4 where 1 and 2 are expected), and not the distance, which parameter_cause names.
    const bool ok0 = close(expected.t[0], got.t[0]), ok1 = close(expected.t[1], got.t[1]);
    if (ok0 == ok1 || agree(scaled(expected, len), got) || !agree(scaled(expected, len), unit_answer(1.0f / len)))
        return "";
    const float wrong = ok0 ? expected.t[1] : expected.t[0];
    return " Measured on your function: one root is right and the other is not (" + show(wrong) + " expected), "
           "and on the same line with d scaled to length 1 both are right: that root's formula divides only "
           "part of its numerator by a = d.d (at |d| = 1, a = 1 hides it), an operator's precedence: the "
           "division binds before the sum or difference it should divide.";
}

/// The roots right but the count not (trial 9, s01_count_two_unset: the two-root branch forgets
/// count = 2): every expected root is in its entry, and the count says fewer. Said first: a relation on
/// the sign of c or of the discriminant can only explain roots that are wrong or absent, not right ones.
inline std::string count_unset_cause(const Roots& expected, const Roots& got) {
    if (expected.count == 0 || got.count >= expected.count || got.count < 0 || has_nan(got)) return "";
    for (int i = 0; i < expected.count; ++i)
        if (!close(expected.t[i], got.t[i])) return "";
    const std::string roots = expected.count == 2 ? "t = " + show(got.t[0]) + " and " + show(got.t[1])
                                                  : "t = " + show(got.t[0]);
    return " Measured on your answer: the roots are right (" + roots + ") but count is " +
           std::to_string(got.count) + ", not " + std::to_string(expected.count) +
           ": where your code finds " + (expected.count == 2 ? "two roots" : "one root") +
           ", it fills t but does not set count = " + std::to_string(expected.count) + ".";
}

/// Count 2 with both entries the same root where the two roots differ (trial 9, s02_t1_copy_t0: t[1]
/// written from t0): one root stored twice, the other never.
inline std::string root_stored_twice_cause(const Roots& expected, const Roots& got) {
    if (expected.count != 2 || got.count != 2 || has_nan(got) || !(got.t[0] == got.t[1]) ||
        close(expected.t[0], expected.t[1]))
        return "";
    const int held = close(expected.t[0], got.t[0]) ? 0 : close(expected.t[1], got.t[0]) ? 1 : -1;
    if (held < 0) return "";
    return " Measured on your answer: count is 2 but both entries hold t = " + show(got.t[0]) + ", the " +
           (held == 0 ? "near" : "far") + " root, where the two roots differ (" + show(expected.t[0]) + " and " +
           show(expected.t[1]) + "): one root stored twice; t[" + std::to_string(1 - held) +
           "] is written from the wrong variable.";
}

/// One root right and the other the product of the two (trial 9, s01_t1_c_over_a: t1 = c / a where the
/// stable pair has c / q): Vieta's c / a = t0 t1. Empty unless both hold and the product is neither root.
inline std::string root_product_cause(const Roots& expected, const Roots& got) {
    if (expected.count != 2 || got.count != 2 || has_nan(got)) return "";
    const float product = expected.t[0] * expected.t[1];
    if (close(product, expected.t[0]) || close(product, expected.t[1])) return "";
    for (int k = 0; k < 2; ++k) {
        if (!close(product, got.t[k])) continue;
        const float other = got.t[1 - k];
        const int right = close(expected.t[0], other) ? 0 : close(expected.t[1], other) ? 1 : -1;
        if (right < 0) continue;
        return " Measured on your answer: one root is right (" + show(other) + ") and the other, " +
               show(got.t[k]) + ", is the product of the two roots (" + show(expected.t[0]) + " x " +
               show(expected.t[1]) + " = c/a, Vieta), where " + show(expected.t[1 - right]) +
               " belongs: your second root is c/a, the product of the roots, which is no root.";
    }
    return "";
}

/// A tangent root off by a factor of exactly 2 on two tangents of different a (trial 9,
/// s01_tangent_over_2a: -h / (2a) with the half h): `tangent(len)` is the function's root on the kit's
/// tangent of a direction of length len, whose right root is `right(len)`. Empty unless the same factor
/// (1/2 or 2) holds on both.
template <class Tangent, class Right>
std::string tangent_factor_cause(const Roots& expected, const Roots& got, Tangent tangent, Right right) {
    if (expected.count != 1 || got.count != 1 || has_nan(got) || expected.t[0] == 0.0f || !cheap_to_measure())
        return "";
    const float ratio = got.t[0] / expected.t[0];
    if (!(close(0.5f, ratio) || close(2.0f, ratio))) return "";
    for (float len : {1.0f, 2.0f}) {
        const Roots there = tangent(len);
        if (there.count != 1 || has_nan(there) || !close(ratio * right(len), there.t[0])) return "";
    }
    return ratio < 1.0f
               ? " Measured on your function: on tangents with directions of length 1 and 2, your tangent root is "
                 "exactly half the right one (" + show(got.t[0]) + " for " + show(expected.t[0]) +
                     "): with the half b, h = o.d, the tangent root is -h/a, not -h/(2a)."
               : " Measured on your function: on tangents with directions of length 1 and 2, your tangent root is "
                 "exactly twice the right one (" + show(got.t[0]) + " for " + show(expected.t[0]) +
                     "): with the whole b = 2 o.d, the tangent root is -b/(2a), not -b/a.";
}

/// A component of the centre the code never reads (trial 9, s02_center_y_typo: f.y = o.y - c.x): on the
/// kit's ray along +z from 5 below the centre (1, 2, 3) of a sphere of radius 2 (roots 3 and 7), the
/// centre alone moved by 0.5 along one axis moves the right roots, whatever the axis; an answer that is
/// the same, bit for bit, names that component. `roots_of(ray, sphere)` is the student's function.
template <class RootsOf>
std::string centre_component_cause(RootsOf roots_of) {
    if (!cheap_to_measure()) return "";
    const Ray ray{{1, 2, -2}, {0, 0, 1}};
    const Sphere ball{{1, 2, 3}, 2};
    const Roots there = roots_of(ray, ball);
    // Two roots found, and exactly one axis whose move leaves them: no roots at all move with nothing.
    if (agree(pair_of(3.0, 7.0), there) || there.count != 2 || has_nan(there)) return "";
    static const char* const axis[] = {"x", "y", "z"};
    int unread = -1, still = 0;
    for (int k = 0; k < 3; ++k) {
        Sphere moved = ball;
        moved.center[k] += 0.5f;
        if (same_answer(there, roots_of(ray, moved))) unread = k, ++still;
    }
    if (still != 1) return "";
    return std::string(" Measured on your function: moving the sphere's centre alone by 0.5 along ") + axis[unread] +
           " moves the roots, and yours stay the same: your code never reads c." + axis[unread] + " (f = o - c, and f." +
           axis[unread] + " = o." + axis[unread] + " - c." + axis[unread] + ").";
}

/// A hit that is an entry beyond the count of the same ray's roots (trial 9, s01_loop_two_roots: the
/// window's loop runs k < 2): `roots` is the roots function's answer for the ray. Empty unless the hit
/// is wrong, equals an entry at or past count and none of the roots.
inline std::string beyond_count_cause(const Roots& roots, const std::optional<float>& expected,
                                      const std::optional<float>& got) {
    if (!got || (expected && close(*expected, *got)) || roots.count < 0 || roots.count > 2 || has_nan(roots))
        return "";
    for (int k = 0; k < roots.count; ++k)
        if (roots.t[k] == *got) return "";
    for (int k = roots.count; k < 2; ++k)
        if (roots.t[k] == *got)
            return " Measured on your function: your hit t = " + show(*got) + " is t[" + std::to_string(k) +
                   "] of this ray's roots, whose count is " + std::to_string(roots.count) +
                   ": an entry beyond the count, which is no root. Read the roots with a loop k < count, "
                   "not k < 2.";
    return "";
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
