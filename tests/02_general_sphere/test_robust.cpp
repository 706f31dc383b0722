// Step 02 grading suite, ★ robust tier: far, tiny, huge and grazing spheres,
// pbrt's test ranges and the ground.
//
// Each case is a handful of rays whose roots a float computation can get
// right to a few ulps, but the textbook formula cannot: the discriminant
// b^2 - 4ac is the difference of two nearly equal large numbers. The expected
// roots are computed in 113-bit precision from the same float inputs
// (tests/support/exact_answers.hpp; precomputed in exact_answers.cpp beside
// this file) and compared in ulps
// (tests/support/robust_grading.hpp). Lecture 03 explains both.

#include <doctest/doctest.h>

#include <limits>

#include <glm/geometric.hpp>

#include "../support/robust_grading.hpp"
#include "raykit/general_sphere.hpp"

using namespace raykit;
using namespace raykit::grading;

namespace {

constexpr int miss = 0, hits = 2;

// The ray from o through target, its direction scaled by `scale` (in float).
Ray aim(glm::vec3 o, glm::vec3 target, float scale = 1) { return {o, (target - o) * scale}; }

// The ray from o towards target with a unit-length direction (in float).
Ray aim_unit(glm::vec3 o, glm::vec3 target) { return {o, glm::normalize(target - o)}; }

// A vector of length k at right angles to `dir`.
glm::vec3 across(glm::vec3 dir, float k) {
    return k * glm::normalize(glm::cross(dir, glm::vec3(0.1f, 0.2f, 1)));
}

// Checks sphere_roots against the exact roots of the same float inputs.
// `count` is what the case claims (a guard against a case that does not test
// what it says: the exact roots must agree).
void expect_accurate(const Ray& ray, const Sphere& sphere, int count, const std::string& why,
                     const std::string& graded) {
    const std::optional<exact::SphereCase> found = exact::sphere_roots(ray, sphere);
    if (!found) return;
    const Roots& exact = found->roots;
    const std::string input = show(found->ray) + "; sphere " + show(found->sphere);
    if (exact.count != count) {
        FAIL_CHECK(report("the case itself", input, "count " + std::to_string(count), show(exact),
                          "The exact roots disagree with the count the case claims: fix the case."));
        return;
    }
    check_case_ulps("sphere_roots(ray, sphere)", input, *found, sphere_roots(found->ray, found->sphere), why, graded);
}

// Each says what goes wrong, not how to write the cure: every failure points to
// lecture 02, section 7, and finding the cure is the exercise.
const std::string far_why =
    "Far away, h^2 and a c' are both about |f|^2 |d|^2: their difference, the discriminant, is small and "
    "keeps few of its digits when computed by subtracting them.";
const std::string scale_why =
    "With |f| ten thousand to ten million radii, h^2 and a c' agree to more digits than even a double holds, "
    "so subtracting them fails in any precision; and in float even a discriminant formed without that "
    "subtraction keeps too few digits, since every product of the inputs rounds.";
const std::string ground_why =
    "The origin is a metre or two above a sphere of radius 1000 or 6.4e6: c' = f.f - r^2 is the difference "
    "of two numbers near r^2 and in float keeps few digits, and the near root is no more accurate than c'. "
    "No rearrangement in float repairs that; near a tangent the count depends on it too.";
const std::string root_why =
    "One root is much smaller than the other: the formula for it subtracts two nearly equal numbers and "
    "keeps few correct digits.";

}  // namespace

TEST_SUITE_BEGIN("robust");

TEST_CASE("a unit sphere 1000 units away" * doctest::description("7. The robust cases")) {
    const std::string graded = graded_forms({Form::float_rewrites, Form::double_textbook, Form::double_rewrite},
                                            {Form::textbook_float});
    const Sphere s{{600, -480, 640}, 1};  // |c| = 1000
    const glm::vec3 o{0, 0, 0}, p{3, 2, -1};
    expect_accurate(aim(o, s.center), s, hits, far_why, graded);
    expect_accurate(aim(o, s.center + glm::vec3(0.5f, 0.3f, -0.2f)), s, hits, far_why, graded);
    expect_accurate(aim(o, s.center + glm::vec3(-0.1f, 0.6f, 0.4f), 0.001f), s, hits, far_why, graded);
    expect_accurate(aim_unit(o, s.center + glm::vec3(0.2f, -0.4f, 0.55f)), s, hits, far_why, graded);
    expect_accurate(aim_unit(p, s.center + glm::vec3(0.0f, 0.25f, -0.3f)), s, hits, far_why, graded);
    expect_accurate(aim(p, s.center + across(s.center - p, 1.05f), 0.25f), s, miss, far_why, graded);
}

TEST_CASE("a unit sphere 10000 units away" * doctest::description("7. The robust cases")) {
    const std::string graded = graded_forms({Form::float_rewrites, Form::double_textbook, Form::double_rewrite},
                                            {Form::textbook_float});
    const Sphere s{{6000, -4800, 6400}, 1};  // |c| = 10000
    const glm::vec3 o{0, 0, 0}, p{-7, 4, 2.5f};
    expect_accurate(aim(o, s.center), s, hits, far_why, graded);
    expect_accurate(aim(o, s.center + glm::vec3(0.5f, 0.3f, -0.2f)), s, hits, far_why, graded);
    expect_accurate(aim(o, s.center + glm::vec3(-0.1f, 0.6f, 0.4f), 0.0001f), s, hits, far_why, graded);
    expect_accurate(aim_unit(o, s.center + glm::vec3(0.2f, -0.4f, 0.55f)), s, hits, far_why, graded);
    expect_accurate(aim_unit(p, s.center + glm::vec3(0.0f, 0.25f, -0.3f)), s, hits, far_why, graded);
    expect_accurate(aim(p, s.center + across(s.center - p, 1.05f), 0.5f), s, miss, far_why, graded);
}

TEST_CASE("a tiny sphere near the origin" * doctest::description("7. The robust cases")) {
    const std::string graded = graded_forms({Form::float_rewrites, Form::double_textbook, Form::double_rewrite},
                                            {Form::textbook_float});
    const Sphere s{{0.3f, -0.4f, 1.2f}, 1e-3f};  // 1.3 away, radius a thousandth
    const glm::vec3 o{0, 0, 0}, p{0.5f, 0.25f, -0.5f};
    expect_accurate(aim(o, s.center), s, hits, far_why, graded);
    expect_accurate(aim(o, s.center + glm::vec3(5e-4f, 0, 0)), s, hits, far_why, graded);
    expect_accurate(aim(o, s.center + glm::vec3(0, -6e-4f, 2e-4f), 3.0f), s, hits, far_why, graded);
    expect_accurate(aim_unit(p, s.center + glm::vec3(2e-4f, 3e-4f, -4e-4f)), s, hits, far_why, graded);
    expect_accurate(aim_unit(p, s.center + glm::vec3(9e-4f, 9e-4f, 0)), s, miss, far_why, graded);
}

TEST_CASE("a huge sphere far away" * doctest::description("7. The robust cases")) {
    const std::string graded = graded_forms({Form::textbook_float, Form::float_rewrites, Form::double_textbook, Form::double_rewrite},
                                            {});
    const Sphere s{{0, 30000, -40000}, 10000};  // 50000 away, radius 10000
    const glm::vec3 o{0, 0, 0}, p{120, -35, 60};
    expect_accurate(aim(o, s.center), s, hits, far_why, graded);
    expect_accurate(aim(o, s.center + glm::vec3(7000, 0, 0), 0.001f), s, hits, far_why, graded);
    expect_accurate(aim_unit(o, s.center + glm::vec3(0, 4000, 3000)), s, hits, far_why, graded);
    expect_accurate(aim_unit(p, s.center + glm::vec3(-9000, 1200, 900)), s, hits, far_why, graded);
    expect_accurate(aim(p, s.center + glm::vec3(11000, 0, 0)), s, miss, far_why, graded);
}

TEST_CASE("a sphere far from the origin with the ray nearby" * doctest::description("7. The robust cases")) {
    const std::string graded = graded_forms({Form::textbook_float, Form::float_rewrites, Form::double_textbook, Form::double_rewrite},
                                            {});
    // World coordinates in the tens of thousands, the ray a few units from the
    // sphere: subtract the centre first, f = o - c, and every later number is small.
    const Sphere s{{12000, -20000, 31000}, 2};
    const glm::vec3 o = s.center + glm::vec3(5, 1, -3);
    expect_accurate({o, {-5, -1, 3}}, s, hits, far_why, graded);
    expect_accurate(aim(o, s.center + glm::vec3(0.5f, 1, 0)), s, hits, far_why, graded);
    expect_accurate(aim_unit(o, s.center + glm::vec3(-1, -1.5f, 0.5f)), s, hits, far_why, graded);
    expect_accurate(aim(o, s.center + glm::vec3(0, 2.5f, 0), 2.0f), s, miss, far_why, graded);
}

TEST_CASE("grazing rays near the silhouette" * doctest::description("7. The robust cases")) {
    const std::string graded = graded_forms({Form::float_rewrites, Form::double_textbook, Form::double_rewrite},
                                            {Form::textbook_float});
    // Rays that pass 1% inside or outside the radius, from 100 and 1000 radii away.
    const Sphere s{{1, 2, 3}, 1};
    const glm::vec3 back = glm::normalize(glm::vec3(1, 0.2f, 0.25f));
    const glm::vec3 side = across(back, 1);
    for (const float distance : {100.0f, 1000.0f}) {
        const glm::vec3 o = s.center - distance * back + 0.99f * side;
        expect_accurate(aim(o, o + back), s, hits, far_why, graded);
        expect_accurate(aim(o, o + back, 3.0f), s, hits, far_why, graded);
        const glm::vec3 p = s.center - distance * back + 1.01f * side;
        expect_accurate(aim(p, p + back), s, miss, far_why, graded);
    }
}

TEST_CASE("a near root much smaller than the far root" * doctest::description("7. The robust cases")) {
    const std::string graded = graded_forms({Form::float_rewrites, Form::double_textbook, Form::double_rewrite},
                                            {Form::textbook_float});
    // The origin close to a big sphere, looking through it: roots about 1 and
    // 2000. With the textbook formula the small root is (-h - sqrt(disc)) / a
    // with h < 0: a difference of two numbers near 1000.
    const Sphere s{{0, -1001, 0}, 1000};
    const glm::vec3 o{0.5f, 0, 0.25f};
    expect_accurate({o, {0, -1, 0}}, s, hits, root_why, graded);
    expect_accurate({o, {0.01f, -1, 0.02f}}, s, hits, root_why, graded);
    expect_accurate(aim_unit(o, {3, -5, 1}), s, hits, root_why, graded);
}

TEST_CASE("the first hit on a far sphere is accurate" * doctest::description("7. The robust cases")) {
    const std::string graded = graded_forms({Form::float_rewrites, Form::double_textbook, Form::double_rewrite},
                                            {Form::textbook_float});
    const Sphere s{{6000, -4800, 6400}, 1};
    for (const Ray& ray : {aim({0, 0, 0}, s.center + glm::vec3(0.3f, 0.2f, 0.1f)),
                           aim_unit({1, 1, 1}, s.center + glm::vec3(-0.2f, 0.5f, 0))}) {
        const std::optional<exact::HitCase> c = exact::sphere_hit(ray, s, 0, inf);
        if (!c) continue;
        check_hit_case("intersect_sphere(ray, sphere, 0, inf)", show(c->ray) + "; sphere " + show(c->sphere), *c,
                       intersect_sphere(c->ray, c->sphere, c->tmin, c->tmax), far_why, graded);
    }
}

TEST_CASE("a tiny sphere seen from very far on pbrt's test ranges" * doctest::description("7. The robust cases")) {
    const std::string graded = graded_forms({Form::double_rewrite},
                                            {Form::textbook_float, Form::float_rewrites, Form::double_textbook});
    // The ranges of pbrt-v4's own sphere tests: a sphere at the world origin,
    // the origin 1e4 to 1e7 radii away, the ray aimed at a point of the
    // sphere's bounding box. Most such rays miss; h^2 - a c, even in double,
    // calls some of them hits.
    const Sphere s{{0, 0, 0}, 0.01f};
    const glm::vec3 o{30000, -40000, 120000};
    expect_accurate(aim(o, s.center), s, hits, scale_why, graded);
    expect_accurate(aim_unit(o, glm::vec3(0.002f, -0.003f, 0.001f)), s, hits, scale_why, graded);
    expect_accurate(aim(o, glm::vec3(-0.0073f, 0.01f, -0.0079f)), s, miss, scale_why, graded);
    expect_accurate(aim(o, glm::vec3(0.0085f, -0.01f, 0.0098f)), s, miss, scale_why, graded);
    // The same near miss turned a quarter about z, from (40000, 30000, 120000): aimed from o itself,
    // its target rounded into the same float direction as the one above.
    expect_accurate(aim(glm::vec3(40000, 30000, 120000), glm::vec3(-0.01f, -0.0082f, -0.0095f)), s, miss,
                    scale_why, graded);

    const Sphere t{{0, 0, 0}, 0.001f};
    const glm::vec3 p{5000, 8000, -20000};
    expect_accurate(aim(p, t.center), t, hits, scale_why, graded);
    expect_accurate(aim(p, glm::vec3(-0.00087f, -0.00062f, -0.00008f)), t, miss, scale_why, graded);
    expect_accurate(aim_unit(p, glm::vec3(-0.0007f, 0.00082f, 0.00036f)), t, miss, scale_why, graded);

    const Sphere u{{0, 0, 0}, 0.25f};
    const glm::vec3 q{-6e6f, 1e6f, 2e6f};
    expect_accurate(aim_unit(q, u.center), u, hits, scale_why, graded);
    expect_accurate(aim_unit(q, glm::vec3(0.2325f, -0.0525f, 0.1875f)), u, miss, scale_why, graded);
    expect_accurate(aim_unit(q, glm::vec3(0.0675f, 0.175f, 0.2475f)), u, miss, scale_why, graded);
    expect_accurate(aim(q, glm::vec3(0.59f, -0.82f, 0.63f)), u, miss, scale_why, graded);
}

TEST_CASE("the ground seen from a metre or two up" * doctest::description("7. The robust cases")) {
    const std::string graded = graded_forms({Form::double_textbook, Form::double_rewrite},
                                            {Form::textbook_float, Form::float_rewrites});
    // A planet-sized or a big ground sphere centred below the camera. The
    // horizon dips by about sqrt(2 H / r) below the horizontal: rays just above
    // it miss, rays just below it hit far away, and c = |f|^2 - r^2 is a tiny
    // difference of two numbers near r^2.
    const Sphere earth{{0, -6.4e6f, 0}, 6.4e6f};  // the Earth in metres; dip 6.8e-4 rad from 1.5 m
    const glm::vec3 eye{0, 1.5f, 0};
    expect_accurate({eye, {1, -0.3f, 0}}, earth, hits, ground_why, graded);
    expect_accurate({eye, {0, -1, 0}}, earth, hits, ground_why, graded);
    expect_accurate({eye, {0.6f, -0.01f, 0.8f}}, earth, hits, ground_why, graded);
    expect_accurate({eye, {1, -0.001f, 0}}, earth, hits, ground_why, graded);
    expect_accurate({eye, {1, -0.0005f, 0}}, earth, miss, ground_why, graded);
    expect_accurate({eye, {0.8f, -0.0001f, -0.6f}}, earth, miss, ground_why, graded);

    const Sphere ground{{0, -1000, 0}, 1000};  // dip 0.049 rad from 1.2 units
    const glm::vec3 cam{0.3f, 1.2f, -0.4f};
    expect_accurate({cam, {0, -0.06f, 1}}, ground, hits, ground_why, graded);
    expect_accurate({cam, {0.5f, -0.02f, 0.5f}}, ground, miss, ground_why, graded);
    expect_accurate({cam, {-2, -0.3f, 1}}, ground, hits, ground_why, graded);
    expect_accurate({cam, {0, -0.045f, -1}}, ground, miss, ground_why, graded);
}

TEST_SUITE_END();
