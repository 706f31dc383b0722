// Shared helpers for the step suites: how values are printed in a failure
// message and how an answer is compared with the expected one.
//
// A failure message is written for a student. It names what was called, the
// input, what was expected, what came back, and one sentence on why the
// expected answer is right. The grader adds the case's name and the lecture
// section (the doctest description of the case).
#pragma once

#include <doctest/doctest.h>

#include <cmath>
#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>

#include <glm/vec2.hpp>
#include <limits>

#include <glm/vec3.hpp>

#include "case_figure.hpp"
#include "float_text.hpp"
#include "ulps.hpp"
#include "raykit/ray.hpp"
#include "raykit/roots.hpp"
#include "raykit/sphere.hpp"

namespace raykit::grading {

/// Infinity, the open end of a window (one definition for every suite of a judge: its files are
/// compiled as one translation unit in the student's build).
inline constexpr float inf = std::numeric_limits<float>::infinity();

/// Shortest text that reads back as the same float ("2", "0.5", "1.00000012").
inline std::string show(float x) { return float_text(x); }

inline std::string show(const glm::vec3& v) {
    return "(" + show(v.x) + ", " + show(v.y) + ", " + show(v.z) + ")";
}

inline std::string show(const glm::vec2& v) { return "(" + show(v.x) + ", " + show(v.y) + ")"; }

inline std::string show(const Ray& ray) {
    return "origin " + show(ray.origin) + ", direction " + show(ray.direction);
}

inline std::string show(const Sphere& s) {
    return "centre " + show(s.center) + ", radius " + show(s.radius);
}

inline std::string show(const Roots& r) {
    if (r.count == 0) {
        if (r.t[0] == 0 && r.t[1] == 0) return "no roots (count 0)";
        return "no roots (count 0), but t = " + show(r.t[0]) + " and " + show(r.t[1]);
    }
    if (r.count == 1) return "1 root (count 1): t[0] = " + show(r.t[0]) + ", t[1] = " + show(r.t[1]);
    if (r.count == 2) return "2 roots (count 2): t = " + show(r.t[0]) + " and " + show(r.t[1]);
    return "count = " + std::to_string(r.count) + " (not 0, 1 or 2)";
}

inline std::string show(const std::optional<float>& hit) {
    return hit ? "a hit at t = " + show(*hit) : "no hit (std::nullopt)";
}

/// The basic tier checks logic, not rounding: answers are exactly
/// representable and any sensible formula lands within a few ulps of them.
inline bool close(float expected, float got) {
    if (std::isnan(got)) return false;
    const float tolerance = 1e-5f * std::fabs(expected) + 1e-6f;
    return std::fabs(got - expected) <= tolerance;
}

/// Builds the message block shared by every failure.
inline std::string report(const std::string& call, const std::string& input,
                          const std::string& expected, const std::string& got,
                          const std::string& why) {
    std::string m = call + "\n";
    if (!input.empty()) m += "  input     " + input + "\n";   // cornell_box() takes none: no empty line
    m += "  expected  " + expected + "\n";
    m += "  got       " + got + "\n";
    if (!why.empty()) m += "  why       " + why + "\n";
    return m;
}

/// Checks a Roots answer against the expected one, contract first (count in
/// {0,1,2}, sorted, tangent repeats its root), then the values.
inline void check_roots(const std::string& call, const std::string& input,
                        const Roots& expected, const Roots& got, const std::string& why) {
    // The case's own why explains its roots; a rule of the contract that does not depend on them (the
    // entries of a miss) is told alone, with_why = false.
    auto fail = [&](const std::string& problem, bool with_why = true) {
        figure::note_failure(call, figure::json(expected), figure::json(got));
        FAIL_CHECK(report(call, input, show(expected), show(got),
                          problem + (why.empty() || !with_why ? "" : " " + why)));
    };
    if (got.count < 0 || got.count > 2) return fail("count must be 0, 1 or 2.");
    if (got.count != expected.count) {
        if (expected.count == 1 && got.count == 2)
            return fail("The discriminant is exactly 0 here: a tangent is one root, not two.");
        if (expected.count == 1 && got.count == 0)
            return fail("The discriminant is exactly 0 here: the ray touches the sphere, so it is one root, not a miss.");
        // Measured: one root at the midpoint -h/a of two expected ones, which is what a tangent gives, is a
        // positive discriminant taken for zero (an epsilon test such as disc < 1e-5).
        if (expected.count == 2 && got.count == 1 && close(expected.t[0] / 2 + expected.t[1] / 2, got.t[0]))
            return fail("You report one root, at the midpoint -h/a of the two expected ones (which lie " +
                        show(expected.t[1] - expected.t[0]) + " apart): your code took this discriminant "
                        "for 0. It is small but positive; only a discriminant of exactly 0 is a tangent, so "
                        "compare it with 0, not with an epsilon.");
        return fail("The number of roots is wrong.");
    }
    // roots.hpp: for count == 0 the entries are 0. A miss that fills t from the formula anyway (the square
    // root of a negative discriminant is NaN) or leaves them unset breaks that.
    if (got.count == 0 && !(got.t[0] == 0 && got.t[1] == 0))
        return fail("A miss leaves both entries of t at 0 (roots.hpp: for count == 0 they are 0); return "
                    "Roots{} or set them to 0, and compute no root before you know there is one.",
                    false);
    // A NaN root fails every ordering rule below: say what it is first (issue 45: NaN roots were told
    // "Roots must be sorted").
    if (got.count >= 1 && (std::isnan(got.t[0]) || (got.count == 2 && std::isnan(got.t[1]))))
        return fail("A root is NaN (not a number): it came from the square root of a negative number, 0 / 0 or "
                    "inf - inf. Know the count first, and take the square root only of a discriminant that is not "
                    "negative.");
    if (got.count == 2 && !(got.t[0] <= got.t[1]))
        return fail("Roots must be sorted: t[0] <= t[1]. Your roots are in the wrong order: the smaller t, the "
                    "nearer point, comes first, whatever the direction.", false);   // a rule of its own: no why
    if (got.count == 1 && !(got.t[0] == got.t[1]))
        return fail("For a tangent both entries hold the same root: t[0] == t[1].");
    for (int i = 0; i < expected.count; ++i) {
        if (close(expected.t[i], got.t[i])) continue;
        // Measured: each root is an expected one with its sign flipped (-4 and -2 for 2 and 4), which a
        // minus lost before b (or h) gives, or L = o - c for c - o in the geometric form.
        bool flipped = true;
        for (int k = 0; k < expected.count; ++k)
            flipped = flipped && close(-expected.t[expected.count - 1 - k], got.t[k]);
        // Only the why's first sentence (its geometry) beside it: a why's later guess (r for r^2) would point
        // away from a sign, which this measurement shows.
        if (flipped) {
            const std::size_t end = why.find(". ");
            figure::note_failure(call, figure::json(expected), figure::json(got));
            FAIL_CHECK(report(call, input, show(expected), show(got),
                              "Your roots are the expected ones with the opposite sign: a sign slip, in the roots' "
                              "formula, which starts from -b: (-b -+ sqrt(b^2 - 4ac)) / (2a), or -h with h = b/2, or "
                              "in the vector they start from, f = o - c (the origin seen from the centre, not c - o; "
                              "geometric form: t_m = L.d with L = c - o)." +
                                  (why.empty() ? "" : " " + (end == std::string::npos ? why : why.substr(0, end + 1)))));
            return;
        }
        return fail("A root has the wrong value.");
    }
}

/// Checks a windowed hit (std::optional<float>) against the expected one.
inline void check_hit(const std::string& call, const std::string& input,
                      const std::optional<float>& expected, const std::optional<float>& got,
                      const std::string& why) {
    const bool ok = expected.has_value() == got.has_value() &&
                    (!expected || close(*expected, *got));
    if (ok) return;
    figure::note_failure(call, figure::json(expected), figure::json(got));
    FAIL_CHECK(report(call, input, show(expected), show(got), why));
}

/// The basic tier's tolerance at `x` (close()'s): how far a sensible formula's root may lie from it.
inline float tolerance_at(float x) { return 1e-5f * std::fabs(x) + 1e-6f; }

/// The basic tier's rules as yes/no answers (check_roots's and check_hit's tolerance, a pair in order,
/// a tangent's two equal roots, a miss's entries at 0), for cases and hidden families that judge
/// before they report.
inline bool agree(const Roots& expected, const Roots& got) {
    if (got.count != expected.count) return false;
    if (got.count == 0 && !(got.t[0] == 0 && got.t[1] == 0)) return false;
    if (got.count == 2 && !(got.t[0] <= got.t[1])) return false;
    if (got.count == 1 && !(got.t[0] == got.t[1])) return false;
    for (int i = 0; i < expected.count; ++i)
        if (!close(expected.t[i], got.t[i])) return false;
    return true;
}

inline bool agree(const std::optional<float>& expected, const std::optional<float>& got) {
    return expected.has_value() == got.has_value() && (!expected || close(*expected, *got));
}

/// The smallest of `roots` inside the closed window [tmin, tmax], or none.
inline std::optional<float> first_in_window(const Roots& roots, float tmin, float tmax) {
    for (int i = 0; i < roots.count; ++i)
        if (roots.t[i] >= tmin && roots.t[i] <= tmax) return roots.t[i];
    return std::nullopt;
}


/// Why a windowed answer is wrong, measured on it where it can be: the expected hit lies exactly at an
/// end of the window, the answer did not take it, and the same function given the window widened by the
/// basic tier's tolerance at each end (`widened`) does take a root close to it. Which root it takes
/// tells the two causes apart: exactly the end (the function skips a t equal to tmin or tmax: it treats
/// the window as open), or a root a few ulps outside the window (the window is closed as it should be;
/// the root itself is off, 1.9999999 for an exact 2). Empty otherwise.
inline std::string window_cause(float tmin, float tmax, const std::optional<float>& expected,
                                const std::optional<float>& got, const std::optional<float>& widened) {
    if (!expected || (got && close(*expected, *got)) || !widened || !close(*expected, *widened)) return "";
    const char* end = *expected == tmin ? "tmin" : *expected == tmax ? "tmax" : nullptr;
    if (!end) return "";
    // A window of one point (trial 9, s02_point_window_rejected: a guard tmin < tmax): the root is both
    // ends, and the ends alone are not what is skipped, so the open-window sentence is not said.
    if (tmin == tmax && *widened == *expected)
        return std::string(" Measured on your answer: the window [") + show(tmin) + ", " + show(tmax) +
               "] gives no hit, and a window a little wider gives t = " + show(*expected) +
               ": your function takes a window of one point as empty (a guard tmin < tmax where tmin <= tmax "
               "belongs).";
    if (*widened == *expected)
        return std::string(" Measured on your answer: the hit t = ") + show(*expected) + " is exactly " + end +
               "; your function skips it, and returns it once the window is a little wider: it treats the "
               "window as open, where it is closed (tmin <= t <= tmax).";
    const bool outside = *widened < tmin || *widened > tmax;
    if (!outside) return "";
    const std::int64_t ulps = ulp_distance(*expected, *widened);
    return std::string(" Measured on your answer: the exact root is ") + show(*expected) + ", exactly " + end +
           ", but your function computes it as " + show(*widened) + ", " + std::to_string(ulps) +
           (ulps == 1 ? " ulp " : " ulps ") + (*widened < *expected ? "below" : "above") +
           ": that root lies outside the closed window by its own rounding error, so skipping it is "
           "right for the value it has. The window's comparisons are not the cause; the root is off "
           "where float gives it exactly (an extra rounding on the way, such as a product with an "
           "approximate 1/a).";
}

/// What own_epsilon measured on a windowed function: `found` when, given the window [0, inf], it takes a
/// hit at t = 1 and at every t down to `kept`, and skips every hit from `dropped` down to 2^-40 (9e-13):
/// a lower bound of its own (t > 1e-3), where the window's tmin is the only one.
struct OwnEpsilon {
    bool found = false;
    float dropped = 0, kept = 0;
};

/// Measures an own epsilon on a windowed function through `hit_at(t)`: the function called with the
/// window [0, inf] on a ray and an object whose nearest hit in it is at t, the object fixed and the ray's
/// direction scaled by 1/t (exact for t a power of two). A hit is taken when the answer is within a
/// thousandth of t. Powers of two from 1 down to 2^-40 find the first skipped one; every smaller one
/// must be skipped too (a bound, not a rounding at one t); then halving the interval between the last
/// taken and the first skipped to a ten-thousandth of it gives the bound's value.
template <class HitAt>
OwnEpsilon own_epsilon(HitAt hit_at) {
    auto taken = [&](float t) {
        const std::optional<float> got = hit_at(t);
        return got.has_value() && std::fabs(*got - t) <= 1e-3f * t;
    };
    OwnEpsilon out;
    if (!taken(1.0f)) return out;
    int first = 0;
    for (int k = 1; k <= 40 && !first; ++k)
        if (!taken(std::ldexp(1.0f, -k))) first = k;
    if (!first) return out;
    for (int k = first + 1; k <= 40; ++k)
        if (taken(std::ldexp(1.0f, -k))) return out;
    float lo = std::ldexp(1.0f, -first), hi = 2 * lo;
    while (hi - lo > 1e-4f * hi) {
        const float mid = lo / 2 + hi / 2;
        if (mid <= lo || mid >= hi) break;
        (taken(mid) ? hi : lo) = mid;
    }
    out.found = true;
    out.dropped = lo;
    out.kept = hi;
    return out;
}

/// A bound in two significant digits, as a student wrote it: 0.001, 0.0001, 1e-5.
inline std::string bound_text(float x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.2g", static_cast<double>(x));
    std::string s = buf;
    const std::size_t e = s.find("e-0");
    if (e != std::string::npos) s.erase(e + 2, 1);
    return s;
}

/// Why a windowed answer skipped the expected hit, measured on the function (own_epsilon through
/// `hit_at`) where the expected hit lies below the bound it measures: an epsilon of the code's own.
/// Empty when the answer is right, no hit was expected, or no such bound is measured. Calls the function
/// again: the caller calls the function under test once more afterwards.
template <class HitAt>
std::string epsilon_cause(float tmin, float tmax, const std::optional<float>& expected,
                          const std::optional<float>& got, HitAt hit_at) {
    if (!expected || (got && close(*expected, *got)) || !(*expected < 1.0f)) return "";
    const OwnEpsilon e = own_epsilon(hit_at);
    if (!e.found || !(*expected < e.dropped)) return "";
    return " Measured on your answer: your code skips hits below t = " + bound_text(e.kept) +
           ", an epsilon of its own. With the window [0, inf] and rays whose hit is at t (their direction "
           "scaled by 1/t), it takes the hit at t = " + show(e.kept) + " and skips it at t = " + show(e.dropped) +
           " and at every t below, down to 1e-12. The window's tmin is the only lower bound: t = " +
           show(*expected) + " lies in [" + show(tmin) + ", " + show(tmax) + "], so it is the hit.";
}

/// check_hit for a call `f(tmin, tmax)` with a window: adds window_cause to the why.
template <class F>
void check_hit_in(const std::string& call, const std::string& input, float tmin, float tmax,
                  const std::optional<float>& expected, F f, const std::string& why) {
    check_hit_in(call, input, tmin, tmax, expected, f, why, [](float) { return std::optional<float>(); });
}

/// check_hit_in with `hit_at(t)` for epsilon_cause (own_epsilon's probe: the function with the window
/// [0, inf] on a ray whose nearest hit is at t): a skipped hit below the code's own bound is named.
template <class F, class HitAt>
void check_hit_in(const std::string& call, const std::string& input, float tmin, float tmax,
                  const std::optional<float>& expected, F f, const std::string& why, HitAt hit_at) {
    // The call under test first (./kit debug stops at it) and, when its answer is not exactly the
    // expected one, the widened window and the epsilon probe for the diagnosis and the call again, so
    // that the last call, which the case's picture records, is still the one checked.
    std::optional<float> got = f(tmin, tmax);
    std::optional<float> widened = got;
    std::string epsilon;
    if (got.has_value() != expected.has_value() || (got && *got != *expected)) {
        widened = f(tmin - tolerance_at(tmin), tmax + tolerance_at(tmax));
        epsilon = epsilon_cause(tmin, tmax, expected, got, hit_at);
        got = f(tmin, tmax);
    }
    check_hit(call, input, expected, got, why + window_cause(tmin, tmax, expected, got, widened) + epsilon);
}

/// check_hit_in for a case whose exact hit lies on an end of the window, where a root within the basic
/// tolerance may fall on either side of it (1.9999999 for an exact 2, from an approximate 1/a): the
/// verdict must not hang on that rounding. So the function is asked again with the window widened by
/// the basic tolerance at each end (as window_cause does): where the root it gives there is close to
/// the exact one but outside the window, its own root lies beyond the end by its own rounding, and
/// skipping it is right; the answer must then be what the window holds without that root (`exact`
/// holds the ray's exact roots). The hidden families accept the same answers, measured on the step's
/// roots function (tests/hidden/rules.hpp, agree_in_window). An open window is still caught: float gives these roots exactly, so a function
/// that skips a root exactly on the end fails, and window_cause names that cause.
template <class F>
void check_hit_at_end(const std::string& call, const std::string& input, float tmin, float tmax, float expected,
                      F f, const std::string& why, const Roots& exact) {
    const std::optional<float> got = f(tmin, tmax);
    if (agree(std::optional<float>(expected), got)) return;
    const std::optional<float> widened = f(tmin - tolerance_at(tmin), tmax + tolerance_at(tmax));
    if (widened && close(expected, *widened) && (*widened < tmin || *widened > tmax)) {
        Roots rest;
        bool dropped = false;
        for (int i = 0; i < exact.count; ++i) {
            if (!dropped && exact.t[i] == expected) {
                dropped = true;
                continue;
            }
            rest.t[rest.count++] = exact.t[i];
        }
        if (agree(first_in_window(rest, tmin, tmax), f(tmin, tmax))) return;   // the last call: the case's
    }
    check_hit_in(call, input, tmin, tmax, std::optional<float>(expected), f, why);
}

}  // namespace raykit::grading
