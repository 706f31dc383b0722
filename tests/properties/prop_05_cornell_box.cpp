// Properties of the reference step 05 over random rays inside and into the Cornell box.

#include <doctest/doctest.h>

#include <limits>
#include <random>

#include "rect_oracle.hpp"
#include "raykit/cornell_box.hpp"
#include "raykit/render.hpp"

using namespace raykit;

TEST_SUITE_BEGIN("properties");

TEST_CASE("cornell box: find_intersection is the nearest of the objects' own hits with the first on a tie") {
    const Scene scene = cornell_box();
    std::mt19937 rng(1111);
    auto uniform = [&](float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(rng); };
    const float inf = std::numeric_limits<float>::infinity();
    int hits = 0;
    for (int i = 0; i < 100000; ++i) {
        const Ray ray{{uniform(-100, 650), uniform(-100, 650), uniform(-900, 650)},
                      {uniform(-1, 1), uniform(-1, 1), uniform(-1, 1)}};
        const float tmin = (i % 4) ? 0.0f : uniform(0, 500), tmax = (i % 3) ? inf : uniform(0, 2000);
        std::optional<Hit> expected;
        for (std::size_t k = 0; k < scene.objects.size(); ++k) {
            const auto t = intersect_rect(ray, scene.objects[k].shape, tmin, tmax);
            if (t && (!expected || *t < expected->t)) expected = Hit{*t, k};
        }
        const auto got = find_intersection(ray, scene, tmin, tmax);
        REQUIRE(got.has_value() == expected.has_value());
        if (got) {
            ++hits;
            REQUIRE(got->t == expected->t);
            REQUIRE(got->index == expected->index);
        }
    }
    CHECK(hits > 10000);  // the random rays really exercise the loop
}

TEST_CASE("cornell box: every ray from inside the box hits a wall") {
    const Scene scene = cornell_box();
    std::mt19937 rng(1212);
    auto uniform = [&](float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(rng); };
    for (int i = 0; i < 100000; ++i) {
        // Inside the box, heading anywhere but out of the open front (z = 0).
        const Ray ray{{uniform(1, 555), uniform(1, 547), uniform(1, 558)},
                      {uniform(-1, 1), uniform(-1, 1), uniform(0.01f, 1)}};
        const auto hit = find_intersection(ray, scene, 0.0f, std::numeric_limits<float>::infinity());
        if (!hit) FAIL("a ray from inside the box escaped (case " << i << ")");
        CHECK(hit->t > 0.0f);
    }
}

TEST_SUITE_END();
