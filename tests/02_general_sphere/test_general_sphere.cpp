// Step 02 grading suite, basic tier: a sphere anywhere, of any size.
//
// The cases of step 01, moved off the origin and scaled: centres are not 0,
// radii are not 1 (and r differs from r^2), directions are not unit length.
// So forgetting the centre, the radius, its square or d.d changes an answer.
// Answers are exact in float (or within a rounding of exact), so the textbook
// formula passes every case. A case's description names the lecture section.

#include <doctest/doctest.h>

#include <cstddef>
#include <limits>
#include <type_traits>

#include "../support/grading.hpp"
#include "../support/relations.hpp"
#include "../support/sphere_facts.hpp"
#include "raykit/general_sphere.hpp"

using namespace raykit;
using namespace raykit::grading;

namespace {

constexpr float not_a_number = std::numeric_limits<float>::quiet_NaN();

Roots two(float t0, float t1) { return Roots{2, {t0, t1}}; }
Roots one(float t) { return Roots{1, {t, t}}; }
Roots none() { return Roots{}; }

// A ray and a sphere the visible cases show (roots 2 and 4; 3 and 9): the calls made before a case's own
// again, to measure hidden state (relations.hpp).
const Ray seen_a{{-1, -2, 3}, {2, 0, 0}}, seen_b{{-4, 1, 0}, {1, 0, 0}};
const Sphere seen_a_ball{{5, -2, 3}, 2}, seen_b_ball{{2, 1, 0}, 3};

// The relations a wrong answer is measured with (relations.hpp), the first broken one said: no state,
// t the ray parameter, t unchanged when the ray and the sphere move together. `call(ray, sphere, k)` asks
// the function with ray and sphere, the direction multiplied by k (and a window divided by it).
template <class Call, class Result, class RootsOf = std::nullptr_t>
std::string measured(const Ray& ray, const Sphere& sphere, const Result& expected, const Result& got, Call call,
                     RootsOf roots_of = nullptr) {
    std::string fact = state_cause([&] { return call(ray, sphere, 1.0f); }, [&] { call(seen_a, seen_a_ball, 1.0f); },
                                   [&] { call(seen_b, seen_b_ball, 1.0f); });
    if (fact.empty())
        fact = translation_cause(ray.origin, sphere.center, expected, got, [&] {
            return call(Ray{ray.origin - sphere.center, ray.direction}, Sphere{{0, 0, 0}, sphere.radius}, 1.0f);
        });
    if constexpr (!std::is_same_v<RootsOf, std::nullptr_t>)   // the roots' formula, on the kit's own probes
        if (fact.empty()) fact = formula_cause(false, roots_of);
    if (fact.empty())
        fact = parameter_cause(ray.direction, expected, got,
                               [&](float k) { return call(ray, sphere, k); });
    return fact;
}

// A wrong answer is measured first, then the call checked is made again, so that the last call, which
// the case's picture records, is the one checked.
void expect_roots(const Ray& ray, const Sphere& sphere, const Roots& expected, const std::string& why) {
    Roots got = sphere_roots(ray, sphere);
    std::string fact, lead;
    if (!agree(expected, got)) {
        // Facts that lead the message (sphere_facts.hpp), after hidden state: the radius through an int,
        // a component from the wrong axis, a = f.f.
        const bool stateless = state_cause([&] { return sphere_roots(ray, sphere); },
                                           [&] { sphere_roots(seen_a, seen_a_ball); },
                                           [&] { sphere_roots(seen_b, seen_b_ball); }).empty();
        // Read off the answer itself first: the roots right and the count not, one root stored twice.
        if (stateless) lead = count_unset_cause(expected, got);
        if (stateless && lead.empty()) lead = root_stored_twice_cause(expected, got);
        if (stateless && lead.empty()) lead = root_product_cause(expected, got);
        if (stateless && lead.empty())
            lead = centre_component_cause([](const Ray& r, const Sphere& s) { return sphere_roots(r, s); });
        if (stateless && lead.empty())
            lead = int_radius_cause(sphere.radius, expected, got,
                                    [&](float r) { return sphere_roots(ray, Sphere{sphere.center, r}); });
        if (stateless && lead.empty())
            lead = axes_cause(expected, got, [&](int k) {
                return sphere_roots({axes_turned(ray.origin, k), axes_turned(ray.direction, k)},
                                    {axes_turned(sphere.center, k), sphere.radius});
            });
        if (stateless && lead.empty())
            lead = a_from_f_cause([](const Ray& r, const Sphere& s) { return sphere_roots(r, s); });
        if (stateless && lead.empty()) lead = zero_over_q_cause(expected, got);
        if (stateless && lead.empty()) lead = q_over_c_cause(expected, got);
        if (lead.empty())
            fact = measured(ray, sphere, expected, got, [](const Ray& r, const Sphere& s, float k) {
                return sphere_roots({r.origin, r.direction * k}, s);
            }, [](const Ray& r, const Sphere& s) { return sphere_roots(r, s); });
        got = sphere_roots(ray, sphere);
    }
    check_roots_led("sphere_roots(ray, sphere)", show(ray) + "; sphere " + show(sphere), expected, got, lead,
                    with_fact(fact, why));
}

// An own epsilon's probe (grading.hpp, own_epsilon): from (-2, 0, 0) with the direction (1/t, 0, 0) the
// ray meets the unit sphere at the origin at t (exactly, for t a power of two), in the window [0, inf].
std::optional<float> hit_at(float t) {
    return intersect_sphere({{-2, 0, 0}, {1 / t, 0, 0}}, Sphere{{0, 0, 0}, 1}, 0, inf);
}

void expect_hit(const Ray& ray, const Sphere& sphere, float tmin, float tmax, std::optional<float> expected,
                const std::string& why) {
    std::string fact;
    const std::optional<float> first = intersect_sphere(ray, sphere, tmin, tmax);
    if (!agree(expected, first)) fact = state_cause([&] { return intersect_sphere(ray, sphere, tmin, tmax); },
                                                    [&] { intersect_sphere(seen_a, seen_a_ball, 0, inf); },
                                                    [&] { intersect_sphere(seen_b, seen_b_ball, 0, inf); });
    if (!agree(expected, first) && fact.empty()) fact = beyond_count_cause(sphere_roots(ray, sphere), expected, first);
    if (!agree(expected, first) && fact.empty()) fact = window_outside_cause(tmin, tmax, expected, first);
    if (!agree(expected, first) && fact.empty()) fact = whole_number_cause(expected, first);
    if (!agree(expected, first) && fact.empty())
        fact = measured(ray, sphere, expected, first, [&](const Ray& r, const Sphere& s, float k) {
            return intersect_sphere({r.origin, r.direction * k}, s, tmin / k, tmax / k);
        });
    check_hit_in("intersect_sphere(ray, sphere, tmin, tmax)",
                 show(ray) + "; sphere " + show(sphere) + "; window [" + show(tmin) + ", " + show(tmax) + "]",
                 tmin, tmax, expected, [&](float lo, float hi) { return intersect_sphere(ray, sphere, lo, hi); },
                 with_fact(fact, why), hit_at);
}

// Most cases use this sphere: centre (5, -2, 3), radius 2. It spans x from 3
// to 7 along the line y = -2, z = 3.
const Sphere ball{{5, -2, 3}, 2};

// Along that line from x = -1 with steps of length 2: x = 3 at t = 2, x = 7 at t = 4.
const Ray through_centre{{-1, -2, 3}, {2, 0, 0}};

// A window cut exactly at a root of through_centre and ball: a root within the basic tolerance of 2 or 4
// may fall on either side of the end, so a root the function's own rounding puts just outside may be
// skipped (grading.hpp, check_hit_at_end).
void expect_hit_at_end(float tmin, float tmax, float expected, const std::string& why) {
    check_hit_at_end("intersect_sphere(ray, sphere, tmin, tmax)",
                     show(through_centre) + "; sphere " + show(ball) + "; window [" + show(tmin) + ", " +
                         show(tmax) + "]",
                     tmin, tmax, expected,
                     [&](float lo, float hi) { return intersect_sphere(through_centre, ball, lo, hi); }, why,
                     two(2, 4));
}

}  // namespace

TEST_SUITE_BEGIN("basic");

// ---- sphere_roots: how many roots, and where -----------------------------------

TEST_CASE("two hits: a ray through the centre of a sphere away from the origin" *
          doctest::description("4. The roots and the discriminant")) {
    expect_roots(through_centre, ball, two(2, 4),
                 "x = -1 + 2t reaches the sphere's near side x = 3 at t = 2 and its far side x = 7 at t = 4. "
                 "f = o - c = (-6, 0, 0), a = 4, h = -12, c' = 32.");
}

TEST_CASE("the centre matters: a ray through the world origin misses a sphere centred elsewhere" *
          doctest::description("1. Moving the centre")) {
    expect_roots({{-3, 0, 0}, {1, 0, 0}}, {{0, 5, 0}, 1}, none(),
                 "The sphere is centred at (0, 5, 0); the x axis passes 5 units from it. "
                 "Roots here would mean the sphere was taken to be centred at the world origin.");
}

TEST_CASE("the centre matters: the roots move with the sphere" * doctest::description("1. Moving the centre")) {
    expect_roots({{0, 0, 0}, {0, 0, 1}}, {{0, 0, 10}, 1}, two(9, 11),
                 "The sphere around (0, 0, 10) covers z from 9 to 11 on the z axis.");
}

TEST_CASE("the radius matters: c' uses r squared" * doctest::description("2. Any radius")) {
    // f = (-6, 0, 0), r = 3: c' = 36 - 9 = 27, h = -6, h^2 - c' = 9.
    const Ray ray{{-4, 1, 0}, {1, 0, 0}};
    const Sphere sphere{{2, 1, 0}, 3};
    // r for r^2 is said only where it is measured (trial 8, issue 54): on the same line with the radius 1,
    // where r = r^2 (roots 5 and 7), the function is right, and so the radius's degree is what can be wrong.
    // A function wrong at r = 1 too has a slip of another kind, and is told the case's geometry alone.
    const bool right_at_radius_1 =
        !agree(two(3, 9), sphere_roots(ray, sphere)) && agree(two(5, 7), sphere_roots(ray, Sphere{sphere.center, 1}));
    expect_roots(ray, sphere, two(3, 9),
                 std::string("The sphere of radius 3 around (2, 1, 0) spans x from -1 to 5: t = 3 and t = 9.") +
                     (right_at_radius_1 ? " Here r = 3 and r^2 = 9 differ, and your function is right with the "
                                          "radius 1, where r = r^2: roots computed from r, not from its square, "
                                          "belong to another sphere."
                                        : ""));
}

TEST_CASE("the radius matters: a small sphere" * doctest::description("2. Any radius")) {
    expect_roots({{1, 1, -2}, {0, 0, 1}}, {{1, 1, 2}, 0.5f}, two(3.5f, 4.5f),
                 "The sphere of radius 0.5 around (1, 1, 2) spans z from 1.5 to 2.5.");
}

TEST_CASE("the radius matters: a tiny sphere has two roots and is no tangent" *
          doctest::description("4. The roots and the discriminant")) {
    // r = 2^-11 and f = (0, 0, -1), d = (0, 0, 1): h = -1, c' = 1 - 2^-22, h^2 - a c' = a r^2 - |f x d|^2
    // = 2^-22 (about 2.4e-7), every one of them exact in float, and so are the roots 1 -+ 2^-11. They lie
    // 0.00098 apart, 89 times the tolerance at 1.
    expect_roots({{2, -1, 4}, {0, 0, 1}}, {{2, -1, 5}, 0.00048828125f}, two(0.99951171875f, 1.00048828125f),
                 "The sphere of radius 1/2048 around (2, -1, 5) spans z from 4.99951171875 to 5.00048828125: "
                 "t = 0.99951171875 and t = 1.00048828125. Its discriminant is r^2 = 2^-22, about 2.4e-7 "
                 "(4 r^2 if you use b^2 - 4ac): small, but a line through a sphere's centre meets it twice, "
                 "however small the sphere.");
}

TEST_CASE("two hits: a ray that does not pass through the centre" *
          doctest::description("4. The roots and the discriminant")) {
    // The line passes 1.2 from the centre of a radius-2 sphere: half chord 1.6.
    expect_roots({{2.2f, 7, -3}, {0, -0.5f, 0}}, {{1, 2, -3}, 2}, two(6.8f, 13.2f),
                 "The line x = 2.2, z = -3 meets the sphere at y = 3.6 and y = 0.4, which with steps of "
                 "length 0.5 from y = 7 are t = 6.8 and t = 13.2.");
}

TEST_CASE("a diagonal ray: every component of o d and c matters" *
          doctest::description("3. Any direction length")) {
    // o - c = -3 d with d = (2, 3, 6), |d| = 7: the distance to the centre is 7 |t - 3|.
    expect_roots({{-5, -11, -14}, {2, 3, 6}}, {{1, -2, 4}, 3.5f}, two(2.5f, 3.5f),
                 "Along this line the distance to the centre is 7|t - 3|; it equals the radius 3.5 at "
                 "t = 2.5 and t = 3.5.");
}

TEST_CASE("no hit: a ray that passes far from the sphere" *
          doctest::description("4. The roots and the discriminant")) {
    expect_roots({{-1, 1, 3}, {1, 0, 0}}, ball, none(),
                 "The line y = 1, z = 3 passes 3 units from the centre (5, -2, 3), more than the radius 2.");
}

TEST_CASE("no hit: a ray just outside the silhouette" * doctest::description("4. The roots and the discriminant")) {
    // y = -2 + (2 + 2^-9): outside by 2^-9, and every product is exact in float.
    expect_roots({{-1, 0.001953125f, 3}, {1, 0, 0}}, ball, none(),
                 "The line passes 2 + 1/512 from the centre: just outside, a miss and not a tangent.");
}

TEST_CASE("one hit: a tangent ray with a direction of length 2" *
          doctest::description("4. The roots and the discriminant")) {
    expect_roots({{1, 0, 3}, {2, 0, 0}}, ball, one(2),
                 "The line y = 0, z = 3 is exactly 2 from the centre: it touches (5, 0, 3) at t = 2. "
                 "a = 4, h = -8, c' = 16: h^2 - a c' = 0.");
}

TEST_CASE("one hit: a tangent ray with a direction of length 1/2" *
          doctest::description("4. The roots and the discriminant")) {
    expect_roots({{-3, 4.5f, -2}, {0, 0, 0.5f}}, {{-3, 4, 1}, 0.5f}, one(6),
                 "The line passes 0.5 from the centre (-3, 4, 1), the radius: it touches (-3, 4.5, 1) "
                 "after 3 units, t = 6 steps of 0.5.");
}

TEST_CASE("origin at the centre: roots at minus and plus the radius over the step" *
          doctest::description("3. Any direction length")) {
    expect_roots({{5, -2, 3}, {0, 0, 4}}, ball, two(-0.5f, 0.5f),
                 "From the centre the surface is 2 units away both ways; with steps of length 4 that is "
                 "t = -0.5 and t = 0.5.");
}

TEST_CASE("origin inside but off centre with a ray towards -x" *
          doctest::description("4. The roots and the discriminant")) {
    expect_roots({{6, -2, 3}, {-0.5f, 0, 0}}, ball, two(-2, 6),
                 "From x = 6 with steps of -0.5 the ray reaches x = 3 at t = 6; behind it, x = 7 at t = -2.");
}

TEST_CASE("origin on the surface looking in: one root is exactly 0" *
          doctest::description("4. The roots and the discriminant")) {
    expect_roots({{3, -2, 3}, {4, 0, 0}}, ball, two(0, 1),
                 "The origin (3, -2, 3) is on the sphere (c' = 0), so t = 0 is a root; the ray leaves at "
                 "x = 7, t = 1.");
}

TEST_CASE("origin on the surface looking out: the other root is behind" *
          doctest::description("4. The roots and the discriminant")) {
    expect_roots({{5, -2, 5}, {0, 0, 2}}, ball, two(-2, 0),
                 "The origin is the sphere's top (5, -2, 5); the line's other crossing, z = 1, is at t = -2.");
}

TEST_CASE("origin on the surface with a tangent direction: one root at t = 0" *
          doctest::description("4. The roots and the discriminant")) {
    expect_roots({{5, -2, 5}, {2, 0, 0}}, ball, one(0),
                 "The origin is the sphere's top (5, -2, 5), so f = (0, 0, 2) and c' = f.f - r^2 = 0; d is "
                 "perpendicular to f, so h = f.d = 0. The discriminant h^2 - a c' is exactly 0: one root, "
                 "t = 0. Here the sum that the stable root pair divides by is 0 too, and 0/0 is NaN: a tangent "
                 "is found from the discriminant, not from the pair.");
    expect_roots({{3, -2, 3}, {0, 3, -4}}, ball, one(0),
                 "o = (3, -2, 3) is on the sphere (f = (-2, 0, 0)) and d = (0, 3, -4) is perpendicular to f: "
                 "h = 0 and c' = 0, one root t = 0, not NaN.");
}

TEST_CASE("sphere behind the ray: both roots negative" *
          doctest::description("5. The closest root in a window")) {
    expect_roots({{9, -2, 3}, {1, 0, 0}}, ball, two(-6, -2),
                 "The roots are of the whole line: behind the origin they are negative, and still reported.");
}

TEST_CASE("a direction of length 1/2 doubles t" * doctest::description("3. Any direction length")) {
    expect_roots({{-1, -2, 3}, {0.5f, 0, 0}}, ball, two(8, 16),
                 "t counts steps of d: with |d| = 1/2 the sphere's sides x = 3 and x = 7 are reached at "
                 "t = 8 and t = 16 (a = d.d = 0.25).");
}

TEST_CASE("root order: a ray travelling towards -x still lists the smaller t first" *
          doctest::description("4. The roots and the discriminant")) {
    expect_roots({{11, -2, 3}, {-2, 0, 0}}, ball, two(2, 4),
                 "Whatever the direction, t[0] <= t[1]: x = 7 at t = 2 comes first, x = 3 at t = 4.");
}

TEST_CASE("root order: a sphere behind a ray travelling towards -x" *
          doctest::description("4. The roots and the discriminant")) {
    expect_roots({{-1, -2, 3}, {-1, 0, 0}}, ball, two(-8, -4),
                 "Both roots are negative; the smaller, t = -8 (x = 7), comes first.");
}

TEST_CASE("a zero direction is no ray: no roots" * doctest::description("6. No sphere and no ray")) {
    expect_roots({{5.5f, -2, 3}, {0, 0, 0}}, ball, none(),
                 "With d = 0 the quadratic's a is 0: there is no line to intersect. Report count 0 (and no NaN).");
}

TEST_CASE("a radius of zero or less is no sphere: no roots" * doctest::description("6. No sphere and no ray")) {
    expect_roots(through_centre, {{5, -2, 3}, 0}, none(),
                 "A radius of 0 describes a point, not a sphere: report no roots.");
    expect_roots(through_centre, {{5, -2, 3}, -2}, none(),
                 "A negative radius describes no sphere, even though r^2 = 4 is a fine number: report no roots.");
}

TEST_CASE("a radius that is NaN or infinite is no sphere: no roots" *
          doctest::description("6. No sphere and no ray")) {
    expect_roots(through_centre, {{5, -2, 3}, not_a_number}, none(),
                 "A NaN radius describes no sphere: report no roots, not NaN roots.");
    expect_roots(through_centre, {{5, -2, 3}, inf}, none(),
                 "An infinite radius describes no sphere: report no roots.");
}

TEST_CASE("a ray holding NaN is no ray: no roots" * doctest::description("6. No sphere and no ray")) {
    expect_roots({{-1, not_a_number, 3}, {2, 0, 0}}, ball, none(),
                 "The origin's y is NaN: the header says such a ray counts as a miss. Report count 0, never a "
                 "NaN root (a test for a == 0 alone lets NaN through: NaN < 0 and NaN == 0 are both false).");
    expect_roots({{-1, -2, 3}, {2, 0, not_a_number}}, ball, none(),
                 "The direction's z is NaN: a, h and the discriminant are NaN. Report count 0, never a NaN root.");
    expect_roots(through_centre, {{5, not_a_number, 3}, 2}, none(),
                 "The centre's y is NaN, so f = o - centre holds NaN: no sphere to meet. Count 0.");
}

TEST_CASE("a ray holding infinity is no ray: no roots" * doctest::description("6. No sphere and no ray")) {
    expect_roots({{-inf, -2, 3}, {2, 0, 0}}, ball, none(),
                 "The origin is at x = -inf: f.d and f.f are infinite and the discriminant is inf - inf = NaN. "
                 "The header says such a ray counts as a miss: count 0, never a NaN root.");
    expect_roots({{-1, -2, 3}, {inf, 0, 0}}, ball, none(),
                 "The direction is infinite, so a = d.d is inf and every root is inf / inf = NaN. Count 0.");
    expect_roots(through_centre, {{inf, -2, 3}, 2}, none(),
                 "The centre is at x = inf: no sphere a finite ray could meet. Count 0.");
}

TEST_CASE("a direction so long that d.d overflows float: no roots or the true roots and never NaN" *
          doctest::description("6. No sphere and no ray")) {
    // The header allows either answer (the same rule as step 01's): count 0 (a float a = d.d is
    // inf), or the true roots 2e-19 and 4e-19 (representable in float, computed in double, as the
    // reference does). Never NaN.
    const Ray ray{{-1, -2, 3}, {2e19f, 0, 0}};
    const Roots got = sphere_roots(ray, ball);
    if (got.count != 0)
        check_roots("sphere_roots(ray, sphere)", show(ray) + "; sphere " + show(ball), two(2e-19f, 4e-19f), got,
                    "|d| = 2e19 is a float, but d.d = 4e38 is beyond the largest float (3.4e38): in float a is "
                    "inf and the roots become inf / inf = NaN. The header allows count 0 here (check that a is "
                    "finite, not only that it is not 0), or the true roots from a wider type.");
}

TEST_CASE("a direction of length 1e-7 is still a ray: roots in steps of d" *
          doctest::description("3. Any direction length")) {
    // Shorter than FLT_EPSILON, yet d.d = 1e-14 is an ordinary float: the roots are asked for.
    const float s = 1e-7f;
    expect_roots({{-1, -2, 3}, {s, 0, 0}}, ball, two(4.0f / s, 8.0f / s),
                 "A direction of length 1e-7 is short, not zero: t counts steps of d, so the sphere's sides "
                 "x = 3 and x = 7 come after 4 / 1e-7 and 8 / 1e-7 steps. A rule that treats a short "
                 "direction (below FLT_EPSILON, say) as zero loses them; only d = 0 is no ray.");
    // Off the centre line: y = -0.8 passes 1.2 from the centre, so x = 5 -+ 1.6.
    expect_roots({{-1, -0.8f, 3}, {s, 0, 0}}, ball, two(4.4f / s, 7.6f / s),
                 "The line y = -0.8 meets the sphere at x = 3.4 and x = 6.6: t = 4.4 / 1e-7 and 7.6 / 1e-7.");
}

TEST_CASE("a tiny direction with subnormal components is still a ray" *
          doctest::description("3. Any direction length")) {
    // |d| = 2^-60 (d.d = 2^-120, still a normal float) and components of 1e-40 (subnormal).
    const float s = 0x1p-60f;
    expect_roots({{-1, -2, 3}, {s, 1e-40f, -1e-40f}}, ball, two(0x1p62f, 0x1p63f),
                 "d = (2^-60, 1e-40, -1e-40): d.d = 2^-120 is a normal float, so the roots are asked for: "
                 "4 / 2^-60 = 2^62 and 2^63. Subnormal components are numbers like any other: never zero "
                 "them, never call such a direction zero.");
}

TEST_CASE("a direction so short that d.d underflows float: no roots or the true roots and never NaN" *
          doctest::description("6. No sphere and no ray")) {
    // |d| = 1e-30: d.d = 1e-60 is 0 in float. The header allows count 0 or the true roots
    // 4e30 and 8e30 (representable in float, computed in double). Never NaN.
    const Ray ray{{-1, -2, 3}, {1e-30f, 0, 0}};
    const Roots got = sphere_roots(ray, ball);
    if (got.count != 0)
        check_roots("sphere_roots(ray, sphere)", show(ray) + "; sphere " + show(ball),
                    two(4.0f / 1e-30f, 8.0f / 1e-30f), got,
                    "|d| = 1e-30 is a float, but d.d = 1e-60 is below the smallest float and becomes 0. The "
                    "header allows count 0 here, or the true roots 4e30 and 8e30 from a wider type; a root "
                    "computed as 0 / 0 is NaN, never allowed.");
}

// ---- intersect_sphere: the closest root in a closed window -----------------------

TEST_CASE("window: the nearer of two roots" * doctest::description("5. The closest root in a window")) {
    expect_hit(through_centre, ball, 0, inf, 2.0f, "Both roots (2 and 4) are in [0, inf]; the closest is t = 2.");
}

TEST_CASE("window: a root that is not a whole number" * doctest::description("5. The closest root in a window")) {
    expect_hit({{-5, -11, -14}, {2, 3, 6}}, {{1, -2, 4}, 3.5f}, 0, inf, 2.5f,
               "The roots are 2.5 and 3.5 (the line passes through the centre at t = 3, and r / |d| = 3.5 / 7 "
               "= 0.5); the hit is t = 2.5, not a whole number.");
}

TEST_CASE("window: a miss is no hit" * doctest::description("5. The closest root in a window")) {
    expect_hit({{-1, 1, 3}, {1, 0, 0}}, ball, 0, inf, std::nullopt, "The line never meets the sphere.");
}

TEST_CASE("window: a tangent is a hit" * doctest::description("5. The closest root in a window")) {
    expect_hit({{1, 0, 3}, {2, 0, 0}}, ball, 0, inf, 2.0f, "A tangent touches the sphere: it is a hit at t = 2.");
}

TEST_CASE("window: a ray holding NaN is no hit" * doctest::description("5. The closest root in a window")) {
    expect_hit({{-1, -2, not_a_number}, {2, 0, 0}}, ball, -inf, inf, std::nullopt,
               "The ray counts as a miss (no roots), so there is no hit even in the window [-inf, inf].");
}

TEST_CASE("window: the near root before tmin gives the far root" *
          doctest::description("5. The closest root in a window")) {
    expect_hit(through_centre, ball, 3, 10, 4.0f, "t = 2 is before tmin = 3, t = 4 is inside [3, 10].");
}

TEST_CASE("window: a window between the two roots is a miss" *
          doctest::description("5. The closest root in a window")) {
    expect_hit(through_centre, ball, 3, 3.5f, std::nullopt,
               "The roots are 2 and 4: t = 2 is before tmin = 3 and t = 4 after tmax = 3.5, so neither is in "
               "[3, 3.5]. Both bounds hold for the same root or it is no hit.");
}

TEST_CASE("window: origin inside the sphere hits the far side" *
          doctest::description("5. The closest root in a window")) {
    expect_hit({{6, -2, 3}, {-0.5f, 0, 0}}, ball, 0, inf, 6.0f,
               "The roots are -2 and 6; -2 is behind the origin, so the hit is the far side, t = 6.");
}

TEST_CASE("window: both roots after tmax is no hit" * doctest::description("5. The closest root in a window")) {
    expect_hit(through_centre, ball, 0, 1, std::nullopt, "Both roots (2 and 4) lie beyond tmax = 1.");
}

TEST_CASE("window: both roots before tmin is no hit" * doctest::description("5. The closest root in a window")) {
    expect_hit(through_centre, ball, 5, 10, std::nullopt, "Both roots (2 and 4) lie before tmin = 5.");
}

TEST_CASE("window: a sphere behind the ray is no hit" * doctest::description("5. The closest root in a window")) {
    expect_hit({{9, -2, 3}, {1, 0, 0}}, ball, 0, inf, std::nullopt,
               "The roots -6 and -2 are both behind tmin = 0.");
}

TEST_CASE("window: a root exactly at tmin counts" * doctest::description("5. The closest root in a window")) {
    expect_hit_at_end(2, 10, 2.0f, "The window is closed: tmin <= t, so t = tmin = 2 is a hit.");
}

TEST_CASE("window: the far root exactly at tmin counts" * doctest::description("5. The closest root in a window")) {
    expect_hit_at_end(4, 10, 4.0f, "t = 2 < tmin, and t = 4 = tmin is inside the closed window.");
}

TEST_CASE("window: a root exactly at tmax counts" * doctest::description("5. The closest root in a window")) {
    expect_hit_at_end(0, 2, 2.0f, "The window is closed: t <= tmax, so t = tmax = 2 is a hit.");
}

TEST_CASE("window: the far root exactly at tmax counts" * doctest::description("5. The closest root in a window")) {
    expect_hit_at_end(3, 4, 4.0f, "t = 2 < tmin = 3, and t = 4 = tmax is inside the closed window.");
}

TEST_CASE("window: a negative tmin accepts roots behind the origin" *
          doctest::description("5. The closest root in a window")) {
    expect_hit({{6, -2, 3}, {-0.5f, 0, 0}}, ball, -10, 10, -2.0f,
               "Any root in the window counts: -2 lies in [-10, 10] and is the smallest.");
}

TEST_CASE("window: tmin greater than tmax is empty" * doctest::description("5. The closest root in a window")) {
    expect_hit(through_centre, ball, 4, 2, std::nullopt,
               "No t satisfies 4 <= t <= 2; both conditions must hold, not either one.");
}

TEST_CASE("window: a one-point window tmin = tmax = 2 holding a root is a hit" *
          doctest::description("5. The closest root in a window")) {
    expect_hit_at_end(2, 2, 2.0f,
                      "tmin == tmax is a window of one point, not an empty one: only tmin > tmax is empty (a test tmin < tmax "
                      "rejects it). The root t = 2 lies in [2, 2], so it is a hit.");
}

TEST_CASE("window: a direction of length 4 returns t in steps of d" *
          doctest::description("3. Any direction length")) {
    expect_hit({{-1, -2, 3}, {4, 0, 0}}, ball, 0, inf, 1.0f,
               "The hit point (3, -2, 3) is o + 1 d: t = 1, not the distance 4.");
}

TEST_CASE("window: a degenerate sphere is no hit" * doctest::description("6. No sphere and no ray")) {
    expect_hit(through_centre, {{5, -2, 3}, -2}, 0, inf, std::nullopt, "A negative radius describes no sphere.");
    expect_hit({{-1, -2, 3}, {0, 0, 0}}, ball, -inf, inf, std::nullopt, "A zero direction describes no ray.");
}

TEST_CASE("window: an origin on the surface with a tangent direction is a hit at t = 0" *
          doctest::description("5. The closest root in a window")) {
    expect_hit({{5, -2, 5}, {2, 0, 0}}, ball, 0, inf, 0.0f,
               "The ray starts on the sphere's top and touches it there: the root t = 0 is at tmin = 0, a hit.");
}

TEST_SUITE_END();
