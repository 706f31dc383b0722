// Properties of the reference step 04 over seeded random rays and rectangles.

#include <doctest/doctest.h>

#include <limits>
#include <random>

#include "rect_oracle.hpp"

using namespace raykit;

namespace {

constexpr int kCases = 200000;

struct Gen {
    std::mt19937 rng;
    explicit Gen(unsigned seed) : rng(seed) {}
    float uniform(float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(rng); }
    Rect rect() {
        const float a = uniform(-10, 10), b = uniform(-10, 10), c = uniform(-10, 10), d = uniform(-10, 10);
        return Rect{static_cast<int>(rng() % 3), uniform(-10, 10), {std::fmin(a, b), std::fmin(c, d)},
                    {std::fmax(a, b), std::fmax(c, d)}};
    }
    Ray ray() {
        glm::vec3 d{uniform(-1, 1), uniform(-1, 1), uniform(-1, 1)};
        if (rng() % 8 == 0) d[rng() % 3] = (rng() % 2) ? 0.0f : -0.0f;  // parallel to some plane
        return Ray{{uniform(-20, 20), uniform(-20, 20), uniform(-20, 20)}, d * uniform(0.1f, 10)};
    }
};

}  // namespace

TEST_SUITE_BEGIN("properties");

TEST_CASE("rectangle: hit or miss agrees with long double outside a rounding margin") {
    Gen g(404);
    const float inf = std::numeric_limits<float>::infinity();
    for (int i = 0; i < kCases; ++i) {
        const Ray ray = g.ray();
        const Rect rect = g.rect();
        const float tmin = (i % 2) ? 0.0f : g.uniform(-30, 30), tmax = (i % 2) ? inf : g.uniform(-30, 30);
        const std::string e = oracles::rect_agrees(ray, rect, tmin, tmax, intersect_rect(ray, rect, tmin, tmax));
        if (!e.empty()) FAIL(e << " (case " << i << ")");
    }
}

TEST_CASE("rectangle: the returned point lies in the plane and inside the bounds") {
    Gen g(505);
    for (int i = 0; i < kCases; ++i) {
        const Ray ray = g.ray();
        const Rect rect = g.rect();
        const auto hit = intersect_rect(ray, rect, 0.0f, std::numeric_limits<float>::infinity());
        if (!hit) continue;
        const glm::vec3 p = point_at(ray, *hit);
        const int k = rect.axis, u = k == 0 ? 1 : 0, v = k == 2 ? 1 : 2;
        const float tol = 1e-4f * (1 + std::fabs(p[u]) + std::fabs(p[v]) + std::fabs(p[k]));
        if (std::fabs(p[k] - rect.offset) > tol) FAIL("the hit point is off the plane (case " << i << ")");
        if (p[u] < rect.lo.x - tol || p[u] > rect.hi.x + tol || p[v] < rect.lo.y - tol || p[v] > rect.hi.y + tol)
            FAIL("the hit point is outside the rectangle (case " << i << ")");
    }
}

TEST_CASE("rectangle: the same point is hit from the other side") {
    Gen g(606);
    const float inf = std::numeric_limits<float>::infinity();
    for (int i = 0; i < kCases / 4; ++i) {
        const Ray ray = g.ray();
        const Rect rect = g.rect();
        const auto hit = intersect_rect(ray, rect, 0.0f, inf);
        if (!hit || oracles::rect_truth(ray, rect, 0.0f, inf) != oracles::Truth::hit) continue;
        // Start as far beyond the plane as the ray started before it, and come back.
        const Ray back{point_at(ray, 2 * *hit), -ray.direction};
        const auto again = intersect_rect(back, rect, 0.0f, inf);
        REQUIRE(again.has_value());
        CHECK(std::fabs(*again - *hit) <= 1e-4f * (1 + *hit));
    }
}

TEST_CASE("rectangle: degenerate input is no hit and never NaN") {
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    const Rect good{2, 5, {-1, -1}, {1, 1}};
    const Ray straight{{0, 0, 0}, {0, 0, 1}};
    REQUIRE(intersect_rect(straight, good, 0, inf) == 5.0f);
    const Rect bad_rects[] = {{3, 5, {-1, -1}, {1, 1}}, {-1, 5, {-1, -1}, {1, 1}}, {2, 5, {1, -1}, {-1, 1}},
                              {2, nan, {-1, -1}, {1, 1}}, {2, 5, {nan, -1}, {1, 1}}, {2, inf, {-1, -1}, {1, 1}}};
    for (const Rect& r : bad_rects) CHECK_FALSE(intersect_rect(straight, r, 0, inf).has_value());
    const Ray bad_rays[] = {{{0, 0, 0}, {0, 0, 0}}, {{nan, 0, 0}, {0, 0, 1}}, {{0, 0, 0}, {0, 0, nan}},
                            {{0, 0, -inf}, {0, 0, 1}}, {{0, 0, 0}, {inf, 0, 1}}, {{0, 0, 5}, {1, 0, 0}}};
    for (const Ray& r : bad_rays) {
        const auto hit = intersect_rect(r, good, -inf, inf);
        CHECK((!hit || std::isfinite(*hit)));
    }
    CHECK_FALSE(intersect_rect(straight, good, nan, inf).has_value());
    CHECK_FALSE(intersect_rect(straight, good, 0, nan).has_value());
}

TEST_SUITE_END();
