// Properties of the reference step 01 over seeded random rays.

#include <doctest/doctest.h>

#include <cstdint>
#include <limits>
#include <random>

#include "oracles.hpp"
#include "raykit/unit_sphere.hpp"

using namespace raykit;

namespace {

constexpr int kRays = 200000;

struct Gen {
    std::mt19937 rng;
    explicit Gen(std::uint32_t seed) : rng(seed) {}
    float uniform(float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(rng); }
    glm::vec3 in_box(float half) { return {uniform(-half, half), uniform(-half, half), uniform(-half, half)}; }
    glm::vec3 direction() {
        glm::vec3 d;
        do d = in_box(1); while (glm::dot(d, d) < 1e-4f);
        return d * std::exp2(uniform(-6, 6));
    }
};

}  // namespace

TEST_SUITE_BEGIN("properties");

TEST_CASE("unit sphere: roots are well formed and classify hits outside the tangent band") {
    Gen g(101);
    for (int i = 0; i < kRays; ++i) {
        const Ray ray{g.in_box(4), g.direction()};
        const Roots r = unit_sphere_roots(ray);
        const std::string form = oracles::roots_well_formed(r);
        const std::string cls = oracles::roots_classified(ray, glm::vec3(0), 1.0f, r);
        if (!form.empty() || !cls.empty()) FAIL(form << cls << " (ray " << i << ")");
        for (int k = 0; k < r.count; ++k) {
            const std::string on = oracles::root_on_surface(ray, glm::vec3(0), 1.0f, r.t[k]);
            if (!on.empty()) FAIL(on << " (ray " << i << ", t = " << r.t[k] << ")");
        }
    }
}

TEST_CASE("unit sphere: the windowed hit is the smallest root in the closed window") {
    Gen g(202);
    for (int i = 0; i < kRays; ++i) {
        const Ray ray{g.in_box(4), g.direction()};
        float tmin = g.uniform(-20, 20), tmax = g.uniform(-20, 20);
        if (i % 3 == 0) tmin = 0, tmax = std::numeric_limits<float>::infinity();
        const std::string w = oracles::hit_in_window(unit_sphere_roots(ray), tmin, tmax,
                                                     intersect_unit_sphere(ray, tmin, tmax));
        if (!w.empty()) FAIL(w << " (ray " << i << ")");
    }
}

TEST_CASE("unit sphere: scaling d by a power of two divides every root by it exactly") {
    Gen g(303);
    for (int i = 0; i < kRays / 4; ++i) {
        const Ray ray{g.in_box(4), g.direction()};
        const Roots r = unit_sphere_roots(ray);
        for (float k : {0.25f, 2.0f, 8.0f}) {
            const Roots s = unit_sphere_roots({ray.origin, k * ray.direction});
            REQUIRE(s.count == r.count);
            for (int j = 0; j < r.count; ++j) REQUIRE(s.t[j] == r.t[j] / k);
        }
    }
}

TEST_CASE("unit sphere: degenerate rays report no hit and never NaN") {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    const Ray bad[] = {
        {{0.5f, 0, 0}, {0, 0, 0}},  {{-0.f, -0.f, -0.f}, {-0.f, 0, 0}}, {{nan, 0, 0}, {1, 0, 0}},
        {{-3, 0, 0}, {nan, 0, 0}},  {{-3, 0, 0}, {inf, 0, 0}},          {{-inf, 0, 0}, {1, 0, 0}},
        {{inf, inf, inf}, {1, 1, 1}}, {{0, 0, 0}, {inf, -inf, 0}},      {{-3, 0, 0}, {1e-30f, 0, 0}},
        // Found by the fuzzer: d.d overflows to inf, and inf / inf made a root NaN.
        {{0x1.fffep-134f, 0x1.fffep-126f, 0}, {0, -0x1.06p+127f, 0x1.ffffdep-64f}},
        {{-3, 0, 0}, {3e19f, 0, 0}},
    };
    for (const Ray& ray : bad) {
        const Roots r = unit_sphere_roots(ray);
        CHECK(oracles::roots_well_formed(r) == "");
        const auto hit = intersect_unit_sphere(ray, 0, inf);
        CHECK((!hit || std::isfinite(*hit)));
    }
    const Ray ok{{-3, 0, 0}, {1, 0, 0}};
    CHECK_FALSE(intersect_unit_sphere(ok, nan, 10).has_value());
    CHECK_FALSE(intersect_unit_sphere(ok, 0, nan).has_value());
    CHECK(intersect_unit_sphere(ok, -inf, inf) == 2.0f);
}

TEST_SUITE_END();
