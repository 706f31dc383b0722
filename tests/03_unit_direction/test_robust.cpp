// Step 03 grading suite, ★ robust tier: both forms on far, tiny, huge and
// grazing spheres, with unit directions.
//
// The expected roots are those of the same float inputs in 113-bit precision
// (tests/support/exact_answers.hpp; precomputed in exact_answers.cpp beside
// this file), compared in ulps
// (tests/support/robust_grading.hpp). A direction from glm::normalize is unit
// only to a rounding, d.d = 1 + e with e about 1e-7; the exact roots use it as
// it is. What the assumption a = 1 costs depends on the discriminant: with
// h^2 - c' as it stands, about t^2 e / (2 sqrt(disc)) (hundreds of ulps at
// t = 1000: the test of a float does not enter); with section 5's leg, which
// keeps the a that h^2 - c' drops, about t e, an ulp or two, which the bound
// leaves room for (lecture 03, section 1).

#include <doctest/doctest.h>

#include <vector>

#include <glm/geometric.hpp>

#include "../support/robust_grading.hpp"
#include "raykit/unit_direction.hpp"

using namespace raykit;
using namespace raykit::grading;

namespace {

constexpr int miss = 0, hits = 2;

struct Shot {
    Ray ray;
    int count;  // what the case claims; the exact roots must agree
};

// A unit ray from o that passes `miss_by` from the centre of s (0: through it).
Shot shot(glm::vec3 o, const Sphere& s, float miss_by, int count) {
    const glm::vec3 to_centre = s.center - o;
    const glm::vec3 side = glm::normalize(glm::cross(to_centre, glm::vec3(0.1f, 0.2f, 1)));
    return {{o, glm::normalize(to_centre + miss_by * side)}, count};
}

using RootsFn = Roots (*)(const Ray&, const Sphere&);

void expect_accurate(const char* call, RootsFn fn, const Sphere& s, const std::vector<Shot>& shots,
                     const std::string& why, const std::string& graded) {
    for (const Shot& shot : shots) {
        const std::optional<exact::SphereCase> found = exact::sphere_roots(shot.ray, s);
        if (!found) continue;
        const Roots& exact = found->roots;
        const std::string input = show(found->ray) + "; sphere " + show(found->sphere);
        if (exact.count != shot.count) {
            FAIL_CHECK(report("the case itself", input, "count " + std::to_string(shot.count), show(exact),
                              "The exact roots disagree with the count the case claims: fix the case."));
            continue;
        }
        check_case_ulps_of(call, input, *found, fn, why, graded);
    }
}

const char* const shortcut = "sphere_roots_unit_dir(ray, sphere)";
const char* const geometric = "sphere_roots_geometric(ray, sphere)";

// Each says what goes wrong, not how to write the cure: the case points to the
// section (5 or 6) that explains it, and finding the cure is the exercise.
const std::string disc_why =
    "h^2 and c' (or |L|^2 and t_m^2) are nearly equal large numbers here: their difference, the "
    "discriminant, keeps few correct digits.";
const std::string unit_why =
    " The direction is unit length only to a rounding (d.d - 1 is about 1e-7): with the discriminant "
    "h^2 - c' as it stands, that alone moves a root by about t^2 (d.d - 1) / (2 sqrt(disc)), hundreds of "
    "ulps at t = 1000, whatever the rounding (lecture 03, section 1).";
const std::string root_why =
    "One root is much smaller than the other: t_m - Dt subtracts two nearly equal numbers and keeps few "
    "correct digits.";

// The scenes, each a sphere and the rays shot at it.
const Sphere far_1e3{{600, -480, 640}, 1};
const Sphere far_1e4{{6000, -4800, 6400}, 1};
const Sphere tiny{{0.3f, -0.4f, 1.2f}, 1e-3f};
const Sphere huge{{0, 30000, -40000}, 10000};
const Sphere grazed{{1, 2, 3}, 1};
const Sphere big{{0, -1001, 0}, 1000};
const Sphere nearby{{12000, -20000, 31000}, 2};

std::vector<Shot> far_shots(const Sphere& s) {
    return {shot({0, 0, 0}, s, 0, hits), shot({0, 0, 0}, s, 0.6f, hits), shot({3, 2, -1}, s, 0.8f, hits),
            shot({-7, 4, 2.5f}, s, 0.3f, hits), shot({3, 2, -1}, s, 1.05f, miss)};
}
std::vector<Shot> tiny_shots() {
    return {shot({0, 0, 0}, tiny, 0, hits), shot({0, 0, 0}, tiny, 6e-4f, hits),
            shot({0.5f, 0.25f, -0.5f}, tiny, 3e-4f, hits), shot({0.5f, 0.25f, -0.5f}, tiny, 1.3e-3f, miss)};
}
std::vector<Shot> huge_shots() {
    return {shot({0, 0, 0}, huge, 0, hits), shot({0, 0, 0}, huge, 7000, hits),
            shot({120, -35, 60}, huge, 9000, hits), shot({120, -35, 60}, huge, 11000, miss)};
}
std::vector<Shot> nearby_shots() {
    const Sphere& s = nearby;
    return {shot(s.center + glm::vec3(5, 1, -3), s, 0, hits), shot(s.center + glm::vec3(5, 1, -3), s, 1.5f, hits),
            shot(s.center + glm::vec3(-2, 4, 1), s, 1, hits), shot(s.center + glm::vec3(-2, 4, 1), s, 2.5f, miss)};
}
std::vector<Shot> grazing_shots() {
    // 1% inside and outside the radius, from 100 and 1000 radii away.
    const glm::vec3 back = glm::normalize(glm::vec3(1, 0.2f, 0.25f));
    std::vector<Shot> out;
    for (const float distance : {100.0f, 1000.0f}) {
        const glm::vec3 o = grazed.center - distance * back;
        out.push_back(shot(o, grazed, 0.99f, hits));
        out.push_back(shot(o, grazed, 1.01f, miss));
    }
    return out;
}
std::vector<Shot> big_shots() {
    // The origin 1 above a sphere of radius 1000, looking through it: roots
    // about 1 and 2000. Every product here is exact in float, so c is exact and
    // only the way the roots are formed decides the error.
    const glm::vec3 o{0.5f, 0, 0.25f};
    return {{{o, {0, -1, 0}}, hits}, {{o, glm::normalize(glm::vec3(0.01f, -1, 0.02f))}, hits},
            {{o, glm::normalize(glm::vec3(3, -5, 1) - o)}, hits}};
}

}  // namespace

TEST_SUITE_BEGIN("robust");

TEST_CASE("shortcut: a unit sphere 1000 units away" * doctest::description("5. Cancellation in the discriminant")) {
    const std::string graded = graded_forms({Form::float_rewrites}, {Form::textbook_float});
    expect_accurate(shortcut, sphere_roots_unit_dir, far_1e3, far_shots(far_1e3), disc_why + unit_why, graded);
}

TEST_CASE("geometric: a unit sphere 1000 units away" * doctest::description("5. Cancellation in the discriminant")) {
    const std::string graded = graded_forms({Form::float_rewrites}, {Form::textbook_float});
    expect_accurate(geometric, sphere_roots_geometric, far_1e3, far_shots(far_1e3), disc_why, graded);
}

TEST_CASE("shortcut: a unit sphere 10000 units away" * doctest::description("5. Cancellation in the discriminant")) {
    const std::string graded = graded_forms({Form::float_rewrites}, {Form::textbook_float});
    expect_accurate(shortcut, sphere_roots_unit_dir, far_1e4, far_shots(far_1e4), disc_why + unit_why, graded);
}

TEST_CASE("geometric: a unit sphere 10000 units away" *
          doctest::description("5. Cancellation in the discriminant")) {
    const std::string graded = graded_forms({Form::float_rewrites}, {Form::textbook_float});
    expect_accurate(geometric, sphere_roots_geometric, far_1e4, far_shots(far_1e4), disc_why, graded);
}

TEST_CASE("shortcut: a tiny sphere near the origin" * doctest::description("5. Cancellation in the discriminant")) {
    const std::string graded = graded_forms({Form::float_rewrites}, {Form::textbook_float});
    expect_accurate(shortcut, sphere_roots_unit_dir, tiny, tiny_shots(), disc_why, graded);
}

TEST_CASE("geometric: a tiny sphere near the origin" * doctest::description("5. Cancellation in the discriminant")) {
    const std::string graded = graded_forms({Form::float_rewrites}, {Form::textbook_float});
    expect_accurate(geometric, sphere_roots_geometric, tiny, tiny_shots(), disc_why, graded);
}

TEST_CASE("shortcut: a huge sphere far away" * doctest::description("5. Cancellation in the discriminant")) {
    const std::string graded = graded_forms({Form::textbook_float, Form::float_rewrites}, {});
    expect_accurate(shortcut, sphere_roots_unit_dir, huge, huge_shots(), disc_why, graded);
}

TEST_CASE("geometric: a huge sphere far away" * doctest::description("5. Cancellation in the discriminant")) {
    const std::string graded = graded_forms({Form::textbook_float, Form::float_rewrites}, {});
    expect_accurate(geometric, sphere_roots_geometric, huge, huge_shots(), disc_why, graded);
}

TEST_CASE("shortcut: a sphere far from the origin with the ray nearby" *
          doctest::description("5. Cancellation in the discriminant")) {
    const std::string graded = graded_forms({Form::textbook_float, Form::float_rewrites}, {});
    expect_accurate(shortcut, sphere_roots_unit_dir, nearby, nearby_shots(), disc_why, graded);
}

TEST_CASE("geometric: a sphere far from the origin with the ray nearby" *
          doctest::description("5. Cancellation in the discriminant")) {
    const std::string graded = graded_forms({Form::textbook_float, Form::float_rewrites}, {});
    expect_accurate(geometric, sphere_roots_geometric, nearby, nearby_shots(), disc_why, graded);
}

TEST_CASE("shortcut: grazing rays near the silhouette" * doctest::description("5. Cancellation in the discriminant")) {
    const std::string graded = graded_forms({Form::float_rewrites}, {Form::textbook_float});
    expect_accurate(shortcut, sphere_roots_unit_dir, grazed, grazing_shots(), disc_why, graded);
}

TEST_CASE("geometric: grazing rays near the silhouette" *
          doctest::description("5. Cancellation in the discriminant")) {
    const std::string graded = graded_forms({Form::float_rewrites}, {Form::textbook_float});
    expect_accurate(geometric, sphere_roots_geometric, grazed, grazing_shots(), disc_why, graded);
}

TEST_CASE("shortcut: a near root much smaller than the far root" *
          doctest::description("6. Cancellation in the roots")) {
    const std::string graded = graded_forms({Form::float_rewrites}, {Form::textbook_float});
    expect_accurate(shortcut, sphere_roots_unit_dir, big, big_shots(), root_why, graded);
}

TEST_CASE("geometric: a near root much smaller than the far root" *
          doctest::description("6. Cancellation in the roots")) {
    const std::string graded = graded_forms({Form::float_rewrites}, {Form::textbook_float});
    expect_accurate(geometric, sphere_roots_geometric, big, big_shots(), root_why, graded);
}

TEST_SUITE_END();
