// Properties of the reference step 02 over seeded random rays and spheres.

#include <doctest/doctest.h>

#include <limits>
#include <random>

#include "oracles.hpp"
#include "raykit/general_sphere.hpp"

using namespace raykit;

namespace {

constexpr int kCases = 200000;

struct Gen {
    std::mt19937 rng;
    explicit Gen(unsigned seed) : rng(seed) {}
    float uniform(float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(rng); }
    glm::vec3 in_box(float half) { return {uniform(-half, half), uniform(-half, half), uniform(-half, half)}; }
    Sphere sphere() { return Sphere{in_box(100), std::exp2(uniform(-8, 8))}; }
    Ray ray_near(const Sphere& s) {
        glm::vec3 d;
        do d = in_box(1); while (glm::dot(d, d) < 1e-4f);
        return Ray{s.center + in_box(8 * s.radius), d * std::exp2(uniform(-6, 6))};
    }
};

}  // namespace

TEST_SUITE_BEGIN("properties");

TEST_CASE("sphere: roots are well formed lie on the sphere and classify hits outside the tangent band") {
    Gen g(707);
    for (int i = 0; i < kCases; ++i) {
        const Sphere s = g.sphere();
        const Ray ray = g.ray_near(s);
        const Roots r = sphere_roots(ray, s);
        std::string e = oracles::roots_well_formed(r) + oracles::roots_classified(ray, s.center, s.radius, r);
        for (int k = 0; k < r.count && e.empty(); ++k) e = oracles::root_on_surface(ray, s.center, s.radius, r.t[k]);
        if (!e.empty()) FAIL(e << " (case " << i << ")");
        const float tmin = g.uniform(-20, 20), tmax = g.uniform(-20, 20);
        const std::string w = oracles::hit_in_window(r, tmin, tmax, intersect_sphere(ray, s, tmin, tmax));
        if (!w.empty()) FAIL(w << " (case " << i << ")");
    }
}

TEST_CASE("sphere: moving ray and sphere together by a power of two leaves the roots nearly unchanged") {
    Gen g(808);
    for (int i = 0; i < kCases / 4; ++i) {
        const Sphere s = g.sphere();
        const Ray ray = g.ray_near(s);
        const Roots r = sphere_roots(ray, s);
        if (r.count != 2) continue;
        // Outside the tangent band the count must not change; the roots move by rounding only.
        if (oracles::line_distance2_over_r2(ray, s.center, s.radius) > 0.99L) continue;
        const glm::vec3 shift{64, -32, 16};
        const Roots m = sphere_roots({ray.origin + shift, ray.direction}, {s.center + shift, s.radius});
        REQUIRE(m.count == 2);
        const float scale = (glm::length(ray.origin - s.center) + s.radius + 150) / glm::length(ray.direction);
        for (int k = 0; k < 2; ++k) CHECK(std::fabs(m.t[k] - r.t[k]) <= 1e-5f * scale);
    }
}

TEST_CASE("sphere: scaling d by a power of two divides every root by it") {
    Gen g(909);
    for (int i = 0; i < kCases / 4; ++i) {
        const Sphere s = g.sphere();
        const Ray ray = g.ray_near(s);
        const Roots r = sphere_roots(ray, s);
        for (float k : {0.5f, 4.0f}) {
            const Roots m = sphere_roots({ray.origin, k * ray.direction}, s);
            REQUIRE(m.count == r.count);
            for (int j = 0; j < r.count; ++j) CHECK(m.t[j] == r.t[j] / k);
        }
    }
}

TEST_CASE("sphere: no sphere and no ray report no hit and never NaN") {
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    const Ray ray{{-3, 0, 0}, {1, 0, 0}};
    for (float r : {0.0f, -0.0f, -1.0f, nan, inf, -inf}) CHECK(sphere_roots(ray, {{0, 0, 0}, r}).count == 0);
    const Sphere s{{0, 0, 0}, 1};
    const Ray bad[] = {{{-3, 0, 0}, {0, 0, 0}}, {{nan, 0, 0}, {1, 0, 0}}, {{-3, 0, 0}, {inf, 0, 0}},
                       {{-inf, 0, 0}, {1, 0, 0}}, {{-3, 0, 0}, {3e19f, 0, 0}}, {{0, 0, 0}, {1e-30f, 0, 0}}};
    for (const Ray& b : bad) {
        CHECK(oracles::roots_well_formed(sphere_roots(b, s)) == "");
        const auto hit = intersect_sphere(b, s, 0, inf);
        CHECK((!hit || !std::isnan(*hit)));
    }
    CHECK_FALSE(intersect_sphere(ray, s, nan, inf).has_value());
    CHECK(sphere_roots({{nan, 0, 0}, {1, 0, 0}}, {{nan, 0, 0}, 1}).count == 0);
}

TEST_SUITE_END();
