// Facts measured on the student's own function (issue 54): relations that every correct answer keeps,
// whatever its formula, asked of the function with the case's own input or with rays the visible cases
// show. A broken relation is a fact about the code, said before any guess ("your function answers
// differently after another call: it keeps state"); a kept one proves nothing and says nothing.
//
// The relations:
//   - no hidden state: the same call answers alike after any other call;
//   - t is the ray parameter: scaling d by k > 0 divides t by k (and the window by k with it), so the same
//     line with d scaled to length 1 has t times |d|;
//   - moving the ray's origin and the sphere together leaves t unchanged (steps 02 and 03);
//   - scaling the whole scene by 2 with the same unit direction doubles t (step 03, whose directions
//     must stay of length 1: there t is not measured against a longer d);
//   - on probe rays of the kit's own, the roots are the formula's, not one of a known variation's
//     (formula_cause: steps 01, 02 and 03).
//
// The sentences name no input: a hidden case's message must not carry its inputs.
#pragma once

#include <cmath>
#include <optional>
#include <string>
#include <utility>

#include <glm/geometric.hpp>

#include "grading.hpp"
#include "remote.hpp"

namespace raykit::grading {

/// Whether the relations may be measured in this case. A measurement is a dozen more calls of the
/// student's code, charged to the step's budget like any: on code that sleeps or computes for long (a
/// sleeper, a slow answer), they would spend that budget and turn the case's own verdict, and the next
/// cases', into time outs. So 16 more calls (as many as a fact makes), each priced at the case's
/// cheapest call, must fit well in what is left of the budget (remote::can_afford_calls). A right call
/// takes microseconds however loaded the machine (the queue is not charged, nor a process's start-up),
/// so right and nearly right code is always measured. A fact is only ever added to a verdict, never the
/// cause of one, so where it is not measured the case says what it says without it.
inline bool cheap_to_measure() { return remote::can_afford_calls(16); }

inline bool same_answer(const Roots& a, const Roots& b) {
    if (a.count != b.count) return false;
    for (int i = 0; i < 2; ++i)
        if (!(a.t[i] == b.t[i] || (std::isnan(a.t[i]) && std::isnan(b.t[i])))) return false;
    return true;
}

inline bool same_answer(const std::optional<float>& a, const std::optional<float>& b) {
    if (a.has_value() != b.has_value()) return false;
    return !a || *a == *b || (std::isnan(*a) && std::isnan(*b));
}

/// No hidden state: `call()` made after `before1()` and again after `before2()` (calls on other inputs)
/// must answer alike. Empty when it does.
template <class Call, class Before1, class Before2>
std::string state_cause(Call call, Before1 before1, Before2 before2) {
    if (!cheap_to_measure()) return "";
    before1();
    const auto first = call();
    before2();
    const auto second = call();
    if (same_answer(first, second)) return "";
    return " Measured on your function: it answers this same call differently after another call (called "
           "once after one ray and once after another, it gave two answers): it keeps state between calls, "
           "such as a static or global variable holding an earlier call's result. Each answer must depend "
           "on this call's arguments alone.";
}

/// |d| (0 for a zero or infinite d). d / |d| is exact when |d| is a power of two, and within a rounding
/// otherwise: the basic tolerance holds a million of those.
inline float length_of(const glm::vec3& d) {
    const double dd = double(d.x) * d.x + double(d.y) * d.y + double(d.z) * d.z;
    if (!(dd > 0.0) || !std::isfinite(dd)) return 0.0f;
    const float len = static_cast<float>(std::sqrt(dd));
    return std::isfinite(len) && len > 0.0f ? len : 0.0f;
}

inline Roots scaled(const Roots& r, float k) {
    Roots out = r;
    for (int i = 0; i < r.count; ++i) out.t[i] = r.t[i] * k;
    return out;
}

inline std::optional<float> scaled(const std::optional<float>& r, float k) {
    return r ? std::optional<float>(*r * k) : std::nullopt;
}

inline bool has_nan(const Roots& r) { return std::isnan(r.t[0]) || std::isnan(r.t[1]); }
inline bool has_nan(const std::optional<float>& r) { return r && std::isnan(*r); }

inline bool has_answer(const Roots& r) { return r.count > 0; }
inline bool has_answer(const std::optional<float>& r) { return r.has_value(); }

/// A root that is not a whole number answered as one (within 1 of it): the fraction lost, as by an int on
/// the way (`int t = r.t[k];`). Measured on the answer alone: every expected value that is a whole number
/// is answered exactly, and every one that is not is answered by a whole number less than 1 away. Empty
/// otherwise, or when every expected value is a whole number.
inline std::string whole_number_cause(const Roots& expected, const Roots& got) {
    if (expected.count == 0 || got.count != expected.count) return "";
    int fractions = 0, at = -1;
    for (int i = 0; i < expected.count; ++i) {
        const float e = expected.t[i], g = got.t[i];
        if (!std::isfinite(e) || !std::isfinite(g) || g != std::trunc(g) || !(std::fabs(g - e) < 1.0f)) return "";
        if (e == std::trunc(e)) {
            if (g != e) return "";
        } else {
            ++fractions;
            if (at < 0) at = i;
        }
    }
    if (fractions == 0) return "";
    return " Measured on your answer: your root is " + show(got.t[at]) + ", expected " + show(expected.t[at]) +
           ": a whole number where the root is not. Is it kept in an int somewhere (int t = ...)? The fraction "
           "is lost there: keep t a float (or a double).";
}

inline std::string whole_number_cause(const std::optional<float>& expected, const std::optional<float>& got) {
    if (!expected || !got) return "";
    return whole_number_cause(Roots{1, {*expected, *expected}}, Roots{1, {*got, *got}});
}

/// t is the ray parameter: measured on `answer(d_scale)`, the function asked on the same line with the
/// direction multiplied by `d_scale` (and a window divided by it). `expected` and `got` are this call's.
/// Says, in this order, what the answers show: the answer is the expected t times |d| (a distance); the
/// function is right with d scaled to length 1 and wrong with this d (it assumes a unit direction); its
/// t does not halve when d doubles. Empty when the direction is of length 1, the answer is right, or
/// the relations hold.
template <class Answer, class Result>
std::string parameter_cause(const glm::vec3& d, const Result& expected, const Result& got, Answer answer) {
    // A NaN answer is a message of its own (check_roots names it), and no relation holds of NaN.
    if (!has_answer(expected) || agree(expected, got) || has_nan(got) || !cheap_to_measure()) return "";
    const float len = length_of(d);
    const Result twice = answer(2.0f);
    if (has_nan(twice)) return "";
    if (len != 0.0f && std::fabs(len - 1.0f) > 1e-3f) {
        // Each claim checked twice: the expected t times |d| may be another root by chance (1 and 2 for
        // |d| = 2), so a distance must also stay the same when d doubles; and code right at length 1 may
        // be wrong only for a short d (one it takes for zero), so a unit direction assumed must also fail
        // at another ordinary length (a wrong hit point may still fall inside the shape at some).
        if (agree(scaled(expected, len), got) && agree(got, twice))
            return " Measured on your function: its t is the expected t times |d| = " + show(len) +
                   ", and stays the same when d doubles: it counts distance along the ray, not steps of d (a "
                   "distance t |d| returned, or d taken as a unit vector somewhere, a = d.d as 1, gives this). t is "
                   "the ray parameter: the point is o + t d, so with a longer d the same point is reached at a "
                   "smaller t.";
        bool wrong_elsewhere = false;   // at a length 2^k, k = +-1 .. +-6 (a short d taken for zero is right there)
        for (int k = 1; k <= 6 && !wrong_elsewhere; ++k)
            for (const float l : {std::ldexp(1.0f, k), std::ldexp(1.0f, -k)})
                wrong_elsewhere = wrong_elsewhere || !agree(scaled(expected, len / l), answer(l / len));
        if (agree(scaled(expected, len), answer(1.0f / len)) && wrong_elsewhere)
            return " Measured on your function: on the same line with d scaled to length 1 it is right, and "
                   "with this d, of length " + show(len) + ", it is not: your code assumes a unit direction "
                   "somewhere (a = d.d taken as 1, or a normalize(d) on the way). t counts steps of d, whatever "
                   "its length; nothing in the task makes d a unit vector.";
    }
    if (!has_answer(got) || !has_answer(twice)) return "";
    if (agree(scaled(got, 0.5f), twice)) return "";
    if (agree(got, twice))
        return " Measured on your function: your t does not change when the direction doubles, where it "
               "must halve: it is a distance along the ray, not the ray parameter (the point is o + t d).";
    return " Measured on your function: your t does not halve when the direction doubles (the same line, "
           "d twice as long), as the ray parameter must: t counts steps of d, so the point is o + t d for "
           "any length of d.";
}

}  // namespace raykit::grading

namespace raykit::grading {

/// Moving the ray's origin and the sphere together leaves t unchanged: measured with both moved so that
/// the centre is at the origin (`moved()`, the function asked with o - c and a centre at 0, where o - c is
/// exact). Empty when the move is inexact, the answer is right, or the relation holds.
template <class Result, class Moved>
std::string translation_cause(const glm::vec3& o, const glm::vec3& c, const Result& expected, const Result& got,
                              Moved moved) {
    if (agree(expected, got) || c == glm::vec3(0.0f) || has_nan(got) || !cheap_to_measure()) return "";
    for (int k = 0; k < 3; ++k)
        if (!std::isfinite(o[k]) || !std::isfinite(c[k]) || double(o[k] - c[k]) != double(o[k]) - double(c[k]))
            return "";
    const Result there = moved();
    if (agree(got, there) || same_answer(got, there) || has_nan(there)) return "";
    if (agree(expected, there))
        return " Measured on your function: moved together with the sphere so that the centre is at the origin "
               "(the same ray relative to the sphere), it is right; here, with the centre elsewhere, it is not. "
               "Moving both together must leave t unchanged: your code uses the origin o where it needs o - c, "
               "the origin seen from the centre.";
    return " Measured on your function: its answer changes when the ray's origin and the sphere move together "
           "(moved so that the centre is at the origin), where t must stay the same: the roots depend on o - c "
           "alone, never on o or c apart.";
}

/// Two roots, sorted (a probe's answer, written out beforehand: no formula of a step ships in a handout).
inline Roots pair_of(double t0, double t1) { return Roots{2, {static_cast<float>(t0), static_cast<float>(t1)}}; }

/// The formula itself, measured on probe rays of the kit's own (never a case's input), all with a unit
/// direction, around the sphere the function is asked about (`roots_of(ray, sphere)`): the unit sphere at
/// the origin (`unit_sphere`, step 01) or the sphere of radius 2 around (1, 2, 3), where r and r^2 differ.
/// The quadratic's probes: the origin inside, r/2 behind the centre, looking along +z (f = (0, 0, -r/2),
/// h = -r/2, c = -3r^2/4: roots -r/2 and 3r/2), and the origin 0.6 r beside the centre (h = 0: roots
/// -+0.8 r). The drawing's: a line 0.6 r from the centre (t_m = 2.5 r, l_m^2 = 0.36 r^2, Dt = 0.8 r).
/// Where the answer is not the right one but exactly what a known variation of the formula gives on that
/// probe (the numbers below, worked out by hand), that variation is said, as what the answer equals.
/// Empty when nothing is measured or nothing matches: a guess is not a measurement.
template <class RootsOf>
std::string formula_cause(bool unit_sphere, RootsOf roots_of, bool geometric = false) {
    if (!cheap_to_measure()) return "";
    const Sphere ball = unit_sphere ? Sphere{{0, 0, 0}, 1} : Sphere{{1, 2, 3}, 2};
    const double r = ball.radius;
    if (!geometric) {
        const std::string lead = " Measured on your function: asked about a ray of the kit's own that starts "
                                 "inside the sphere, ";
        const Ray inside{ball.center + glm::vec3(0, 0, -0.5f * ball.radius), {0, 0, 1}};
        const Roots right = pair_of(-0.5 * r, 1.5 * r), got = roots_of(inside, ball);
        if (has_nan(got)) return "";
        if (got.count == 0)
            return lead + "it finds no root. From inside, c = f.f - r^2 is negative, so the discriminant "
                   "h^2 - a c is positive whatever h, and there are always two roots: the sign of c (f.f - r^2, "
                   "not + r^2) or of the discriminant (h^2 - a c, not a c - h^2) is turned.";
        struct Variant { Roots roots; const char* says; };
        const Variant variants[] = {
            {pair_of(-0.3228757 * r, 2.3228757 * r),
             "it gives what the half-b form (-h -+ sqrt(h^2 - a c)) / a gives with h = 2 f.d, the whole b: in the "
             "half-b form h is half of b, h = f.d."},
            {pair_of(-1.3027756 * r, 2.3027756 * r),
             "it gives what (-h -+ sqrt(h^2 - 4 a c)) / a gives: with h = b/2 the discriminant is h^2 - a c; the "
             "4 belongs to the whole b, b^2 - 4ac."},
            {pair_of(-0.25 * r, 0.75 * r),
             "its roots are half the right ones: with h = b/2 the roots are (-h -+ sqrt(h^2 - a c)) / a, divided "
             "by a, not by 2a."},
            {pair_of(-1.0 * r, 3.0 * r),
             "its roots are twice the right ones: with the whole b the roots are (-b -+ sqrt(b^2 - 4ac)) / (2a), "
             "divided by 2a, not by a."},
            // c = f.f - r for r = 2: h = -1, c = -1, roots 1 -+ sqrt(2). (With r = 1 it is the right answer.)
            {unit_sphere ? right : pair_of(-0.41421356, 2.41421356),
             "it gives the roots of c = f.f - r: the constant term uses r squared, c = f.f - r^2."},
        };
        if (!agree(right, got))
            for (const Variant& v : variants)
                if (agree(v.roots, got)) return lead + v.says;
        // The square root's fraction dropped: beside the centre the roots are -+0.8 r.
        const Ray beside{ball.center + glm::vec3(0.6f * ball.radius, 0, 0), {0, 0, 1}};
        const Roots there = roots_of(beside, ball);
        const float half = there.count == 2 ? 0.5f * (there.t[1] - there.t[0]) : -1.0f;
        // Its own prediction checked too: an int square root keeps the roots' middle (-h/a, 0 here) right,
        // where one root stored twice (trial 9, s02_t1_copy_t0) moves it.
        if (there.count == 2 && half >= 0 && half == std::floor(half) && !close(float(0.8 * r), half) &&
            std::fabs(there.t[0] + there.t[1]) <= 1e-3f * float(r))
            return " Measured on your function: on a ray of the kit's own whose roots are -+" + show(float(0.8 * r)) +
                   ", its roots lie -+" + show(half) + " from their middle, a whole number: the square root loses "
                   "its fraction on the way (kept in an int: int s = std::sqrt(...)).";
        return "";
    }
    const Ray line{ball.center + glm::vec3(0.6f * ball.radius, -2.5f * ball.radius, 0), {0, 1, 0}};
    const Roots got = roots_of(line, ball);
    if (agree(pair_of(1.7 * r, 3.3 * r), got) || has_nan(got)) return "";
    const std::string on = " Measured on your function: on a line of the kit's own that passes " +
                           show(float(0.6 * r)) + " from the centre of a sphere of radius " + show(ball.radius) +
                           " (t_m = " + show(float(2.5 * r)) + ", l_m^2 = " + show(float(0.36 * r * r)) +
                           ", Dt = " + show(float(0.8 * r)) + "), ";
    if (got.count == 0)
        return on + "it finds no root, where Dt^2 = r^2 - l_m^2 is positive: check the signs in l_m^2 = |L|^2 - "
                    "t_m^2 and in Dt^2 = r^2 - l_m^2.";
    if (got.count != 2 || !close(float(2.5 * r), 0.5f * (got.t[0] + got.t[1]))) return "";
    const float half = 0.5f * (got.t[1] - got.t[0]);
    std::string says = "t_m is right, so the error is in l_m^2 = |L|^2 - t_m^2 or in Dt^2 = r^2 - l_m^2.";
    // Dt^2 = r^2 + l_m^2 is sqrt(1.36) r; Dt^2 = r - l_m^2 (r = 2) is sqrt(0.56).
    if (close(float(1.1661904 * r), half))
        says = "that is Dt^2 = r^2 + l_m^2: the sign of l_m^2 = |L|^2 - t_m^2 is turned.";
    else if (!unit_sphere && close(0.74833148f, half))
        says = "that is Dt^2 = r - l_m^2: the radius is used where its square belongs.";
    return on + "your roots are centred on the right t_m but lie " + show(half) + " from it: " + says;
}

/// Scaling the whole scene (origin, centre and radius) by 2 with the same unit direction doubles every
/// root: measured with the case's own ray and sphere, where that scaling is exact. Broken by a term of the
/// wrong degree (r where r^2 belongs). Empty when the relation holds or is not measured.
template <class Result, class Scaled>
std::string scene_scale_cause(const Result& expected, const Result& got, Scaled scaled_call) {
    if (agree(expected, got) || has_nan(got) || !has_answer(got) || !cheap_to_measure()) return "";
    const Result twice = scaled_call();
    if (has_nan(twice) || agree(scaled(got, 2.0f), twice)) return "";
    return " Measured on your function: with the whole scene twice as large (origin, centre and radius "
           "doubled, the same unit direction) every root must double, and yours do not: a term has the wrong "
           "degree, such as r where r^2 belongs, or a length where its square belongs.";
}

/// The first sentence of a case's why (its geometry): beside a measured fact, the rest of a why, which may
/// guess at a cause, is left out so that no message states a cause the measurement contradicts.
inline std::string first_sentence(const std::string& why) {
    const std::size_t at = why.find(". ");
    return at == std::string::npos ? why : why.substr(0, at + 1);
}

/// A measured fact (a relation's sentence, with its leading space) before the case's own why.
inline std::string with_fact(const std::string& fact, const std::string& why) {
    if (fact.empty()) return why;
    return fact.substr(1) + " " + first_sentence(why);
}

}  // namespace raykit::grading
