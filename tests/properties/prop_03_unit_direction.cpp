// Properties of the reference step 03: both forms agree with the long-double geometry on unit rays.

#include <doctest/doctest.h>

#include <random>

#include "oracles.hpp"
#include "raykit/unit_direction.hpp"

using namespace raykit;

TEST_SUITE_BEGIN("properties");

TEST_CASE("unit direction: both forms are well formed on the sphere and classify hits") {
    std::mt19937 rng(1010);
    auto uniform = [&](float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(rng); };
    for (int i = 0; i < 200000; ++i) {
        const Sphere s{{uniform(-50, 50), uniform(-50, 50), uniform(-50, 50)}, std::exp2(uniform(-6, 6))};
        glm::vec3 d;
        do d = {uniform(-1, 1), uniform(-1, 1), uniform(-1, 1)}; while (glm::dot(d, d) < 1e-2f);
        const Ray ray{s.center + s.radius * glm::vec3{uniform(-8, 8), uniform(-8, 8), uniform(-8, 8)},
                      glm::normalize(d)};
        for (const Roots& r : {sphere_roots_unit_dir(ray, s), sphere_roots_geometric(ray, s)}) {
            std::string e = oracles::roots_well_formed(r) + oracles::roots_classified(ray, s.center, s.radius, r);
            for (int k = 0; k < r.count && e.empty(); ++k) e = oracles::root_on_surface(ray, s.center, s.radius, r.t[k]);
            if (!e.empty()) FAIL(e << " (case " << i << ")");
        }
    }
}

TEST_SUITE_END();
