// Step 02 grading suite, ★ robust tier: far, tiny, huge and grazing spheres.
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

constexpr float inf = std::numeric_limits<float>::infinity();
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
void expect_accurate(const Ray& ray, const Sphere& sphere, int count, const std::string& why) {
    const std::optional<exact::SphereCase> found = exact::sphere_roots(ray, sphere);
    if (!found) return;
    const Roots& exact = found->roots;
    const std::string input = show(found->ray) + "; sphere " + show(found->sphere);
    if (exact.count != count) {
        FAIL_CHECK(report("the case itself", input, "count " + std::to_string(count), show(exact),
                          "The exact roots disagree with the count the case claims: fix the case."));
        return;
    }
    check_roots_ulps("sphere_roots(ray, sphere)", input, exact, sphere_roots(found->ray, found->sphere), why);
}

const std::string far_why =
    "Far away, h^2 and a c are both about |f|^2 |d|^2 and their difference loses most of its digits: "
    "compute the discriminant as a (r^2 - |f - (h/a) d|^2).";
const std::string root_why =
    "When one root is much smaller than the other, -h + sqrt(disc) cancels: take the root that adds terms "
    "of the same sign, q = -(h + sign(h) sqrt(disc)), and get the other from c / q.";

}  // namespace

TEST_SUITE_BEGIN("robust");

TEST_CASE("a unit sphere 1000 units away" * doctest::description("7. The robust cases")) {
    const Sphere s{{600, -480, 640}, 1};  // |c| = 1000
    const glm::vec3 o{0, 0, 0}, p{3, 2, -1};
    expect_accurate(aim(o, s.center), s, hits, far_why);
    expect_accurate(aim(o, s.center + glm::vec3(0.5f, 0.3f, -0.2f)), s, hits, far_why);
    expect_accurate(aim(o, s.center + glm::vec3(-0.1f, 0.6f, 0.4f), 0.001f), s, hits, far_why);
    expect_accurate(aim_unit(o, s.center + glm::vec3(0.2f, -0.4f, 0.55f)), s, hits, far_why);
    expect_accurate(aim_unit(p, s.center + glm::vec3(0.0f, 0.25f, -0.3f)), s, hits, far_why);
    expect_accurate(aim(p, s.center + across(s.center - p, 1.05f), 0.25f), s, miss, far_why);
}

TEST_CASE("a unit sphere 10000 units away" * doctest::description("7. The robust cases")) {
    const Sphere s{{6000, -4800, 6400}, 1};  // |c| = 10000
    const glm::vec3 o{0, 0, 0}, p{-7, 4, 2.5f};
    expect_accurate(aim(o, s.center), s, hits, far_why);
    expect_accurate(aim(o, s.center + glm::vec3(0.5f, 0.3f, -0.2f)), s, hits, far_why);
    expect_accurate(aim(o, s.center + glm::vec3(-0.1f, 0.6f, 0.4f), 0.0001f), s, hits, far_why);
    expect_accurate(aim_unit(o, s.center + glm::vec3(0.2f, -0.4f, 0.55f)), s, hits, far_why);
    expect_accurate(aim_unit(p, s.center + glm::vec3(0.0f, 0.25f, -0.3f)), s, hits, far_why);
    expect_accurate(aim(p, s.center + across(s.center - p, 1.05f), 0.5f), s, miss, far_why);
}

TEST_CASE("a tiny sphere near the origin" * doctest::description("7. The robust cases")) {
    const Sphere s{{0.3f, -0.4f, 1.2f}, 1e-3f};  // 1.3 away, radius a thousandth
    const glm::vec3 o{0, 0, 0}, p{0.5f, 0.25f, -0.5f};
    expect_accurate(aim(o, s.center), s, hits, far_why);
    expect_accurate(aim(o, s.center + glm::vec3(5e-4f, 0, 0)), s, hits, far_why);
    expect_accurate(aim(o, s.center + glm::vec3(0, -6e-4f, 2e-4f), 3.0f), s, hits, far_why);
    expect_accurate(aim_unit(p, s.center + glm::vec3(2e-4f, 3e-4f, -4e-4f)), s, hits, far_why);
    expect_accurate(aim_unit(p, s.center + glm::vec3(9e-4f, 9e-4f, 0)), s, miss, far_why);
}

TEST_CASE("a huge sphere far away" * doctest::description("7. The robust cases")) {
    const Sphere s{{0, 30000, -40000}, 10000};  // 50000 away, radius 10000
    const glm::vec3 o{0, 0, 0}, p{120, -35, 60};
    expect_accurate(aim(o, s.center), s, hits, far_why);
    expect_accurate(aim(o, s.center + glm::vec3(7000, 0, 0), 0.001f), s, hits, far_why);
    expect_accurate(aim_unit(o, s.center + glm::vec3(0, 4000, 3000)), s, hits, far_why);
    expect_accurate(aim_unit(p, s.center + glm::vec3(-9000, 1200, 900)), s, hits, far_why);
    expect_accurate(aim(p, s.center + glm::vec3(11000, 0, 0)), s, miss, far_why);
}

TEST_CASE("a sphere far from the origin with the ray nearby" * doctest::description("7. The robust cases")) {
    // World coordinates in the tens of thousands, the ray a few units from the
    // sphere: subtract the centre first, f = o - c, and every later number is small.
    const Sphere s{{12000, -20000, 31000}, 2};
    const glm::vec3 o = s.center + glm::vec3(5, 1, -3);
    expect_accurate({o, {-5, -1, 3}}, s, hits, far_why);
    expect_accurate(aim(o, s.center + glm::vec3(0.5f, 1, 0)), s, hits, far_why);
    expect_accurate(aim_unit(o, s.center + glm::vec3(-1, -1.5f, 0.5f)), s, hits, far_why);
    expect_accurate(aim(o, s.center + glm::vec3(0, 2.5f, 0), 2.0f), s, miss, far_why);
}

TEST_CASE("grazing rays near the silhouette" * doctest::description("7. The robust cases")) {
    // Rays that pass 1% inside or outside the radius, from 100 and 1000 radii away.
    const Sphere s{{1, 2, 3}, 1};
    const glm::vec3 back = glm::normalize(glm::vec3(1, 0.2f, 0.25f));
    const glm::vec3 side = across(back, 1);
    for (const float distance : {100.0f, 1000.0f}) {
        const glm::vec3 o = s.center - distance * back + 0.99f * side;
        expect_accurate(aim(o, o + back), s, hits, far_why);
        expect_accurate(aim(o, o + back, 3.0f), s, hits, far_why);
        const glm::vec3 p = s.center - distance * back + 1.01f * side;
        expect_accurate(aim(p, p + back), s, miss, far_why);
    }
}

TEST_CASE("a near root much smaller than the far root" * doctest::description("7. The robust cases")) {
    // The origin close to a big sphere, looking through it: roots about 1 and
    // 2000. With the textbook formula the small root is (-h - sqrt(disc)) / a
    // with h < 0: a difference of two numbers near 1000.
    const Sphere s{{0, -1001, 0}, 1000};
    const glm::vec3 o{0.5f, 0, 0.25f};
    expect_accurate({o, {0, -1, 0}}, s, hits, root_why);
    expect_accurate({o, {0.01f, -1, 0.02f}}, s, hits, root_why);
    expect_accurate(aim_unit(o, {3, -5, 1}), s, hits, root_why);
}

TEST_CASE("the first hit on a far sphere is accurate" * doctest::description("7. The robust cases")) {
    const Sphere s{{6000, -4800, 6400}, 1};
    for (const Ray& ray : {aim({0, 0, 0}, s.center + glm::vec3(0.3f, 0.2f, 0.1f)),
                           aim_unit({1, 1, 1}, s.center + glm::vec3(-0.2f, 0.5f, 0))}) {
        const std::optional<exact::HitCase> c = exact::sphere_hit(ray, s, 0, inf);
        if (!c) continue;
        check_hit_ulps("intersect_sphere(ray, sphere, 0, inf)", show(c->ray) + "; sphere " + show(c->sphere), c->t,
                       intersect_sphere(c->ray, c->sphere, c->tmin, c->tmax), far_why);
    }
}

TEST_SUITE_END();
