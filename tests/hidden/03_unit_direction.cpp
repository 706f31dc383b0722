// Hidden cases of step 03 (see hidden.hpp): both rewrites for a unit direction.

#include "hidden.hpp"
#include "raykit/unit_direction.hpp"
#include "rules.hpp"

using namespace raykit;
using namespace raykit::hidden;

namespace {

struct Input {
    Ray ray;
    Sphere sphere;
};

// The contract asks for a unit direction: normalized in float, or an axis.
Input random_input(Draw& d, int kind) {
    const Sphere s{d.around({0, 0, 0}, 0, 50), d.uniform(0.2f, 10)};
    glm::vec3 o, target;
    switch (kind) {
        case 0: o = d.around(s.center, 1.5f * s.radius, 8 * s.radius), target = d.around(s.center, 0, 0.7f * s.radius); break;
        case 1: {
            o = d.around(s.center, 2 * s.radius, 8 * s.radius);
            const glm::vec3 side = glm::normalize(glm::cross(o - s.center, d.direction()));
            target = s.center + d.uniform(1.3f, 3) * s.radius * side;
            break;
        }
        case 2: o = d.around(s.center, 0, 0.8f * s.radius), target = o + d.direction(); break;
        default: {
            o = d.around(s.center, 1.5f * s.radius, 8 * s.radius);
            target = o + (o - d.around(s.center, 0, 0.6f * s.radius));  // pointing away: behind
        }
    }
    return {aimed(o, target, 1), s};
}

Input exact_input(Draw& d) {
    const glm::vec3 c{static_cast<float>(d.integer(-20, 20)), static_cast<float>(d.integer(-20, 20)), 0};
    const float r = static_cast<float>(d.integer(1, 4));
    const int a = d.integer(0, 2);
    const float s = d.sign();
    const float k = r + static_cast<float>(d.integer(1, 30)) * 0.5f;
    const float y = d.coin() ? r * d.sign() : 0.0f;
    return {{c + d.permute({-s * k, y, 0}, a), d.permute({s, 0, 0}, a)}, {c, r}};
}

// An origin exactly on the sphere: tangent (h = 0), heading in or heading out.
Input surface_input(Draw& d) {
    const Sphere s{{static_cast<float>(d.integer(-20, 20)), static_cast<float>(d.integer(-20, 20)),
                    static_cast<float>(d.integer(-20, 20))},
                   static_cast<float>(d.integer(1, 3))};
    return {surface_ray(d, s.center, s.radius, d.integer(0, 2), true), s};
}

void family(const char* function, const char* family, int kind) {
    Draw draw(family);
    for (int i = 0; i < draws; ++i) {
        Input in = kind < 4 ? random_input(draw, kind) : kind == 4 ? exact_input(draw)
                 : kind == 5 ? surface_input(draw) : random_input(draw, 0);
        // kind 6: the header's rule, count 0, for input holding NaN or infinity (not the reference's answer).
        if (kind == 6) spoil(draw, in.ray, &in.sphere.center, i % 2, false, false);
        const Roots expected = kind == 6 ? Roots{} : remote::reference<Roots>(function, in.ray, in.sphere);
        const Roots got = std::string(function) == "sphere_roots_unit_dir" ? sphere_roots_unit_dir(in.ray, in.sphere)
                                                                            : sphere_roots_geometric(in.ray, in.sphere);
        if (!agree(expected, got)) {
            grading::check_roots(std::string(function) + "(ray, sphere)",
                                 input_note(i, grading::show(in.ray) + "; sphere " + grading::show(in.sphere)),
                                 expected, got,
                                 kind == 6 ? "Input holding NaN or infinity counts as a miss (unit_direction.hpp): "
                                             "count 0, never a NaN root."
                                           : "With |d| = 1 the roots are the same as step 02's.");
            return;
        }
    }
}

}  // namespace

TEST_SUITE_BEGIN("hidden");

TEST_CASE("sphere_roots_unit_dir on random rays through and past the sphere" *
          doctest::description("1. When the direction has length 1")) {
    family("sphere_roots_unit_dir", "03 unit through", 0);
    family("sphere_roots_unit_dir", "03 unit miss", 1);
}

TEST_CASE("sphere_roots_unit_dir from inside and behind and on exact tangents" *
          doctest::description("3. Ahead, behind and inside")) {
    family("sphere_roots_unit_dir", "03 unit inside", 2);
    family("sphere_roots_unit_dir", "03 unit behind", 3);
    family("sphere_roots_unit_dir", "03 unit exact", 4);
}

TEST_CASE("sphere_roots_unit_dir from origins on the surface: tangent and heading in and out" *
          doctest::description("3. Ahead, behind and inside")) {
    family("sphere_roots_unit_dir", "03 unit surface", 5);
}

TEST_CASE("sphere_roots_unit_dir on input holding NaN or infinity" *
          doctest::description("1. When the direction has length 1")) {
    family("sphere_roots_unit_dir", "03 unit contract", 6);
}

TEST_CASE("sphere_roots_geometric on random rays through and past the sphere" *
          doctest::description("2. The same roots from a drawing")) {
    family("sphere_roots_geometric", "03 geometric through", 0);
    family("sphere_roots_geometric", "03 geometric miss", 1);
}

TEST_CASE("sphere_roots_geometric from inside and behind and on exact tangents" *
          doctest::description("3. Ahead, behind and inside")) {
    family("sphere_roots_geometric", "03 geometric inside", 2);
    family("sphere_roots_geometric", "03 geometric behind", 3);
    family("sphere_roots_geometric", "03 geometric exact", 4);
}

TEST_CASE("sphere_roots_geometric from origins on the surface: tangent and heading in and out" *
          doctest::description("3. Ahead, behind and inside")) {
    family("sphere_roots_geometric", "03 geometric surface", 5);
}

TEST_CASE("sphere_roots_geometric on input holding NaN or infinity" *
          doctest::description("2. The same roots from a drawing")) {
    family("sphere_roots_geometric", "03 geometric contract", 6);
}

TEST_SUITE_END();
