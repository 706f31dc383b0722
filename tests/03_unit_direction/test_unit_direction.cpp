// Step 03 grading suite, basic tier: the unit-direction shortcut and the
// geometric form.
//
// Every case runs on a unit direction (axis-aligned ones are exactly unit in
// float; the others come from glm::normalize and are unit to a rounding). The
// expected roots are those of step 02's general formula for the same ray, in
// high precision (tests/support/exact_answers.hpp; precomputed in
// exact_answers.cpp beside this file: step 03 does not link step 02).
// Cases come in pairs, one for each function, so that a student who has
// written one of the two sees it graded.

#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <vector>

#include <glm/geometric.hpp>

#include "../support/grading.hpp"
#include "../support/exact_answers.hpp"
#include "../support/relations.hpp"
#include "../support/sphere_facts.hpp"
#include "raykit/unit_direction.hpp"

using namespace raykit;
using namespace raykit::grading;

namespace {

constexpr float not_a_number = std::numeric_limits<float>::quiet_NaN();

Roots two(float t0, float t1) { return Roots{2, {t0, t1}}; }
Roots one(float t) { return Roots{1, {t, t}}; }
Roots none() { return Roots{}; }

std::string input(const Ray& ray, const Sphere& sphere) { return show(ray) + "; sphere " + show(sphere); }

// A ray and a sphere the visible cases show (ahead and inside, below): the calls made before a case's own
// again, to measure hidden state (relations.hpp).
const Ray seen_a{{2, -1, 0}, {0, 0, 1}}, seen_b{{2.5f, -1, 4}, {1, 0, 0}};
const Sphere seen_ball{{2, -1, 4}, 1.5f};

// Facts measured on a wrong answer (relations.hpp), the first broken relation said: no state, t unchanged
// when the ray and the sphere move together, t doubled with the whole scene, and the formula on the kit's
// own probe rays. Every probe keeps the direction of length 1, the step's precondition: a shortcut that
// is wrong for a longer d is right by design, so t is never measured against a scaled d here.
// `lead` gets a fact of sphere_facts.hpp, said before the contract's sentence (check_roots_led).
template <class Fn>
Roots measured_roots(Fn fn, const Ray& ray, const Sphere& sphere, const Roots& expected, std::string& fact,
                     bool geometric, std::string& lead) {
    Roots got = fn(ray, sphere);
    if (agree(expected, got)) return got;
    fact = state_cause([&] { return fn(ray, sphere); }, [&] { fn(seen_a, seen_ball); }, [&] { fn(seen_b, seen_ball); });
    if (fact.empty()) fact = whole_number_cause(expected, got);
    // The axes renamed: a component from the wrong axis, said before the translation and scale relations,
    // which such code breaks too and so would misname; then the stable pair's slips.
    if (fact.empty())
        lead = axes_cause(expected, got, [&](int k) {
            return fn(Ray{axes_turned(ray.origin, k), axes_turned(ray.direction, k)},
                      Sphere{axes_turned(sphere.center, k), sphere.radius});
        });
    if (fact.empty() && lead.empty() && !geometric) lead = zero_over_q_cause(expected, got);
    if (fact.empty() && lead.empty() && !geometric) lead = q_over_c_cause(expected, got);
    if (fact.empty() && lead.empty() && !geometric) lead = stable_4ac_cause(false, fn);
    if (!lead.empty()) return fn(ray, sphere);
    if (fact.empty())
        fact = translation_cause(ray.origin, sphere.center, expected, got, [&] {
            return fn(Ray{ray.origin - sphere.center, ray.direction}, Sphere{{0, 0, 0}, sphere.radius});
        });
    if (fact.empty() && sphere.radius > 0 && std::isfinite(2 * sphere.radius))
        fact = scene_scale_cause(expected, got, [&] {
            return fn(Ray{2.0f * ray.origin, ray.direction}, Sphere{2.0f * sphere.center, 2 * sphere.radius});
        });
    if (fact.empty()) fact = formula_cause(false, fn, geometric);
    return fn(ray, sphere);   // the call checked made last, so that the case's picture records it
}

void expect_shortcut(const Ray& ray, const Sphere& sphere, const Roots& expected, const std::string& why) {
    std::string fact, lead;
    const Roots got = measured_roots([](const Ray& r, const Sphere& s) { return sphere_roots_unit_dir(r, s); },
                                     ray, sphere, expected, fact, false, lead);
    check_roots_led("sphere_roots_unit_dir(ray, sphere)", input(ray, sphere), expected, got, lead, with_fact(fact, why));
}

void expect_geometric(const Ray& ray, const Sphere& sphere, const Roots& expected, const std::string& why) {
    std::string fact, lead;
    const Roots got = measured_roots([](const Ray& r, const Sphere& s) { return sphere_roots_geometric(r, s); },
                                     ray, sphere, expected, fact, true, lead);
    check_roots_led("sphere_roots_geometric(ray, sphere)", input(ray, sphere), expected, got, lead, with_fact(fact, why));
}

// Centre (2, -1, 4), radius 1.5 (so r = 1.5 and r^2 = 2.25 differ).
const Sphere ball{{2, -1, 4}, 1.5f};

// The sphere ahead: along +z from z = 0, the centre projects at t_m = 4.
const Ray ahead{{2, -1, 0}, {0, 0, 1}};
// The sphere behind: from z = 10 along +z, t_m = -6.
const Ray behind{{2, -1, 10}, {0, 0, 1}};
// The origin inside, 0.5 from the centre, looking along +x: t_m = -0.5.
const Ray inside{{2.5f, -1, 4}, {1, 0, 0}};
// A line 0.9 from the centre: t_m = 5, l_m^2 = 0.81, half chord 1.2.
const Ray offset{{2.9f, -6, 4}, {0, 1, 0}};
// A line exactly 1.5 from the centre: a tangent at t_m = 4.
const Ray tangent{{2, 0.5f, 0}, {0, 0, 1}};
// A line 2 from the centre: a miss.
const Ray passing{{2, 1, 0}, {0, 0, 1}};
// The origin on the surface, 1.5 along +x from the centre: f = (1.5, 0, 0), c' = 0.
const glm::vec3 on_surface{3.5f, -1, 4};
const Ray surface_tangent{on_surface, {0, 1, 0}};  // h = 0: one root, t = 0
const Ray surface_in{on_surface, {-1, 0, 0}};      // roots 0 and 3
const Ray surface_out{on_surface, {1, 0, 0}};      // roots -3 and 0
// A diagonal unit direction (1, 2, 2) / 3 from 6 units before the centre.
const Ray diagonal{{0, -5, 0}, glm::normalize(glm::vec3(1, 2, 2))};

}  // namespace

TEST_SUITE_BEGIN("basic");

// ---- the shortcut: t = -h -+ sqrt(h^2 - c) ---------------------------------------

TEST_CASE("shortcut: a sphere ahead gives two positive roots" *
          doctest::description("3. Ahead, behind and inside")) {
    expect_shortcut(ahead, ball, two(2.5f, 5.5f),
                    "f = o - c = (0, 0, -4), h = f.d = -4, c' = 16 - 2.25: t = 4 -+ 1.5. "
                    "h < 0 means the centre is ahead, and -h is where the ray passes it.");
}

TEST_CASE("shortcut: a sphere behind gives two negative roots" *
          doctest::description("3. Ahead, behind and inside")) {
    expect_shortcut(behind, ball, two(-7.5f, -4.5f),
                    "h = f.d = 6 > 0: the centre is behind, at t = -6, and the roots are -6 -+ 1.5.");
}

TEST_CASE("shortcut: origin inside gives one root on each side" *
          doctest::description("3. Ahead, behind and inside")) {
    expect_shortcut(inside, ball, two(-2, 1),
                    "c' = 0.25 - 2.25 < 0 (the origin is inside), h = 0.5: t = -0.5 -+ 1.5.");
}

TEST_CASE("shortcut: a line that misses the centre" * doctest::description("1. When the direction has length 1")) {
    expect_shortcut(offset, ball, two(3.8f, 6.2f),
                    "The line passes 0.9 from the centre at t = 5; the half chord is sqrt(2.25 - 0.81) = 1.2.");
}

TEST_CASE("shortcut: a tangent is one root" * doctest::description("1. When the direction has length 1")) {
    expect_shortcut(tangent, ball, one(4),
                    "h = -4 and c' = 2.25 + 16 - 2.25 = 16: h^2 - c' = 0 exactly, one root t = -h = 4.");
}

TEST_CASE("shortcut: a line 2 from the centre misses" * doctest::description("1. When the direction has length 1")) {
    expect_shortcut(passing, ball, none(), "h^2 - c' = 16 - (4 + 16 - 2.25) < 0: no roots.");
}

TEST_CASE("shortcut: a diagonal unit direction" * doctest::description("1. When the direction has length 1")) {
    expect_shortcut(diagonal, ball, two(4.5f, 7.5f),
                    "The centre is 6 units along the ray, so the roots are 6 -+ 1.5; with |d| = 1, t is a distance.");
}

TEST_CASE("shortcut: origin on the surface with a tangent direction is one root at t = 0" *
          doctest::description("1. When the direction has length 1")) {
    expect_shortcut(surface_tangent, ball, one(0),
                    "The origin is on the sphere (c' = f.f - r^2 = 0) and d is perpendicular to f (h = 0): "
                    "h^2 - c' = 0, one root t = 0. Here the sum that the stable root pair divides by is 0 too, "
                    "and 0/0 is NaN: a tangent is found from the discriminant, not from the pair.");
}

TEST_CASE("shortcut: origin on the surface heading in" * doctest::description("3. Ahead, behind and inside")) {
    expect_shortcut(surface_in, ball, two(0, 3),
                    "c' = 0 (the origin is on the sphere) and h = -1.5: t = 1.5 -+ 1.5, so 0 and 3.");
}

TEST_CASE("shortcut: origin on the surface heading out" * doctest::description("3. Ahead, behind and inside")) {
    expect_shortcut(surface_out, ball, two(-3, 0),
                    "c' = 0 and h = 1.5: t = -1.5 -+ 1.5, so -3 behind and 0 at the origin.");
}

TEST_CASE("shortcut: a ray holding NaN is a miss" * doctest::description("1. When the direction has length 1")) {
    expect_shortcut({{2, not_a_number, 0}, {0, 0, 1}}, ball, none(),
        "The origin's y is NaN: the header says such a ray counts as a miss. Report count 0, never a NaN root.");
    expect_shortcut({{2, -1, 0}, {0, not_a_number, 1}}, ball, none(),
        "The direction holds NaN (it is no unit vector, but the header still asks for count 0, never a NaN root).");
    expect_shortcut(ahead, {{2, -1, not_a_number}, 1.5f}, none(), "The centre's z is NaN: no sphere to meet. Count 0.");
}

TEST_CASE("shortcut: a ray holding infinity is a miss" * doctest::description("1. When the direction has length 1")) {
    expect_shortcut({{2, -1, -inf}, {0, 0, 1}}, ball, none(),
        "The origin is at z = -inf: the values that decide the roots are inf - inf = NaN. The header says "
        "such a ray counts as a miss: count 0, never a NaN root.");
    expect_shortcut(ahead, {{2, -1, inf}, 1.5f}, none(), "The centre is at z = inf: no sphere a finite ray could meet. Count 0.");
}

TEST_CASE("shortcut: a radius of zero or less is no sphere" *
          doctest::description("1. When the direction has length 1")) {
    expect_shortcut(ahead, {{2, -1, 4}, 0}, none(), "A radius of 0 describes no sphere: no roots.");
    expect_shortcut(ahead, {{2, -1, 4}, -1.5f}, none(), "A negative radius describes no sphere: no roots.");
}

// ---- the geometric form: t_m -+ Dt --------------------------------------------------

TEST_CASE("geometric: a sphere ahead has t_m > 0" * doctest::description("3. Ahead, behind and inside")) {
    expect_geometric(ahead, ball, two(2.5f, 5.5f),
                     "L = c - o = (0, 0, 4), t_m = L.d = 4, l_m^2 = 16 - 16 = 0, Dt = 1.5: t = 4 -+ 1.5.");
}

TEST_CASE("geometric: a sphere behind has t_m < 0" * doctest::description("3. Ahead, behind and inside")) {
    expect_geometric(behind, ball, two(-7.5f, -4.5f),
                     "L = (0, 0, -6), t_m = -6: the closest approach is behind the origin; "
                     "both roots t_m -+ Dt are negative and still reported.");
}

TEST_CASE("geometric: origin inside puts the roots on both sides" *
          doctest::description("3. Ahead, behind and inside")) {
    expect_geometric(inside, ball, two(-2, 1),
                     "L = (-0.5, 0, 0), t_m = -0.5, l_m^2 = 0, Dt = 1.5: t = -2 and t = 1. "
                     "Inside, Dt > |t_m|; do not reject the ray because t_m < 0.");
}

TEST_CASE("geometric: a line that misses the centre" * doctest::description("2. The same roots from a drawing")) {
    expect_geometric(offset, ball, two(3.8f, 6.2f),
                     "t_m = 5, l_m^2 = 25.81 - 25 = 0.81, Dt^2 = 2.25 - 0.81 = 1.44: t = 5 -+ 1.2.");
}

TEST_CASE("geometric: a tangent is one root" * doctest::description("2. The same roots from a drawing")) {
    expect_geometric(tangent, ball, one(4),
                     "t_m = 4 and l_m^2 = 18.25 - 16 = 2.25 = r^2: Dt = 0, one root t = t_m.");
}

TEST_CASE("geometric: a line 2 from the centre misses" * doctest::description("2. The same roots from a drawing")) {
    expect_geometric(passing, ball, none(), "l_m^2 = 4 > r^2 = 2.25: the line passes outside, no roots.");
}

TEST_CASE("geometric: a diagonal unit direction" * doctest::description("2. The same roots from a drawing")) {
    expect_geometric(diagonal, ball, two(4.5f, 7.5f),
                     "L = (2, 4, 4), t_m = L.d = 6 and l_m = 0: t = 6 -+ 1.5.");
}

TEST_CASE("geometric: origin on the surface with a tangent direction is one root at t = 0" *
          doctest::description("2. The same roots from a drawing")) {
    expect_geometric(surface_tangent, ball, one(0),
                     "L = (-1.5, 0, 0), t_m = L.d = 0 and l_m^2 = 2.25 = r^2: Dt = 0, one root t = t_m = 0. "
                     "The stable pair's small root divides 0 by 0 here (t_m and Dt are both 0): a tangent is "
                     "found from Dt^2 = 0, not from the pair.");
}

TEST_CASE("geometric: origin on the surface heading in" * doctest::description("3. Ahead, behind and inside")) {
    expect_geometric(surface_in, ball, two(0, 3),
                     "t_m = 1.5 and l_m = 0, Dt = 1.5: t = 0 and t = 3.");
}

TEST_CASE("geometric: origin on the surface heading out" * doctest::description("3. Ahead, behind and inside")) {
    expect_geometric(surface_out, ball, two(-3, 0),
                     "t_m = -1.5 and l_m = 0, Dt = 1.5: t = -3 and t = 0. The centre is behind, yet t = 0 is "
                     "a root.");
}

TEST_CASE("geometric: a ray holding NaN is a miss" * doctest::description("2. The same roots from a drawing")) {
    expect_geometric({{2, not_a_number, 0}, {0, 0, 1}}, ball, none(),
        "The origin's y is NaN: the header says such a ray counts as a miss. Report count 0, never a NaN root.");
    expect_geometric({{2, -1, 0}, {0, not_a_number, 1}}, ball, none(),
        "The direction holds NaN (it is no unit vector, but the header still asks for count 0, never a NaN root).");
    expect_geometric(ahead, {{2, -1, not_a_number}, 1.5f}, none(), "The centre's z is NaN: no sphere to meet. Count 0.");
}

TEST_CASE("geometric: a ray holding infinity is a miss" * doctest::description("2. The same roots from a drawing")) {
    expect_geometric({{2, -1, -inf}, {0, 0, 1}}, ball, none(),
        "The origin is at z = -inf: the values that decide the roots are inf - inf = NaN. The header says "
        "such a ray counts as a miss: count 0, never a NaN root.");
    expect_geometric(ahead, {{2, -1, inf}, 1.5f}, none(), "The centre is at z = inf: no sphere a finite ray could meet. Count 0.");
}

TEST_CASE("geometric: a radius of zero or less is no sphere" *
          doctest::description("2. The same roots from a drawing")) {
    expect_geometric(ahead, {{2, -1, 4}, 0}, none(), "A radius of 0 describes no sphere: no roots.");
    expect_geometric(ahead, {{2, -1, 4}, -1.5f}, none(), "A negative radius describes no sphere: no roots.");
}

// ---- both forms agree with step 02 on unit directions ------------------------------

namespace {

// Rays with unit directions in every octant, against spheres of several sizes.
struct UnitScene {
    Ray ray;
    Sphere sphere;
};

std::vector<UnitScene> unit_scenes() {
    std::vector<UnitScene> out;
    const Sphere spheres[] = {{{2, -1, 4}, 1.5f}, {{-3, 0.5f, -2}, 0.75f}, {{0.25f, 6, 1}, 3}};
    const glm::vec3 origins[] = {{0, 0, 0}, {1, -2, 0.5f}, {-4, 3, 2}};
    const glm::vec3 offsets[] = {{0, 0, 0}, {0.3f, -0.2f, 0.1f}, {-0.5f, 0.4f, 0.6f}};
    for (const Sphere& s : spheres)
        for (const glm::vec3& o : origins)
            for (const glm::vec3& k : offsets) {
                const glm::vec3 toward = s.center + k * s.radius - o;
                out.push_back({{o, glm::normalize(toward)}, s});   // sphere ahead
                out.push_back({{o, -glm::normalize(toward)}, s});  // the same sphere behind
            }
    return out;
}

}  // namespace

TEST_CASE("shortcut: the same roots as step 02 on 54 unit rays" *
          doctest::description("1. When the direction has length 1")) {
    for (const UnitScene& s : unit_scenes())
        if (const std::optional<exact::SphereCase> c = exact::sphere_roots(s.ray, s.sphere))
            expect_shortcut(c->ray, c->sphere, c->roots,
                            "With |d| = 1 the shortcut must give the roots of the general quadratic of step 02.");
}

TEST_CASE("geometric: the same roots as step 02 on 54 unit rays" *
          doctest::description("2. The same roots from a drawing")) {
    for (const UnitScene& s : unit_scenes())
        if (const std::optional<exact::SphereCase> c = exact::sphere_roots(s.ray, s.sphere))
            expect_geometric(c->ray, c->sphere, c->roots,
                             "With |d| = 1 the geometric form must give the roots of the general quadratic of step 02.");
}

TEST_SUITE_END();
