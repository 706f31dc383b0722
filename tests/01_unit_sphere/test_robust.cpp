// Step 01 grading suite, ★ robust tier: the unit sphere seen from far away
// and by grazing rays.
//
// Optional. The expected roots are those of the same float inputs in 113-bit
// precision (tests/support/exact_answers.hpp; precomputed in
// exact_answers.cpp beside this file), compared in ulps
// (tests/support/robust_grading.hpp). Every case points to lecture 01,
// section 6, which says why the textbook formula fails here and where lecture
// 03 cures it; come back to these after step 03.

#include <doctest/doctest.h>

#include <vector>

#include <glm/geometric.hpp>

#include "../support/robust_grading.hpp"
#include "raykit/unit_sphere.hpp"

using namespace raykit;
using namespace raykit::grading;

namespace {

constexpr int miss = 0, hits = 2;
const Sphere unit{{0, 0, 0}, 1};

// A ray from o that passes `miss_by` from the centre (0: through it), its
// direction scaled to length `length`.
Ray shot(glm::vec3 o, float miss_by, float length) {
    const glm::vec3 side = glm::normalize(glm::cross(o, glm::vec3(0.1f, 0.2f, 1)));
    return {o, length * glm::normalize(miss_by * side - o)};
}

void expect_accurate(const Ray& ray, int count, const std::string& why, const std::string& graded) {
    const std::optional<exact::SphereCase> found = exact::sphere_roots(ray, unit);
    if (!found) return;
    const Roots& exact = found->roots;
    if (exact.count != count) {
        FAIL_CHECK(report("the case itself", show(found->ray), "count " + std::to_string(count), show(exact),
                          "The exact roots disagree with the count the case claims: fix the case."));
        return;
    }
    check_case_ulps("unit_sphere_roots(ray)", show(found->ray), *found, unit_sphere_roots(found->ray), why, graded);
}

// Says what goes wrong, not how to write the cure: the pointer to the lecture
// section comes with every failure, and finding the cure is the exercise.
const std::string why =
    "Seen from far away, the two terms whose difference is the discriminant are large and nearly equal: "
    "the difference keeps few correct digits, so the roots, or whether there are any, come out wrong.";

}  // namespace

TEST_SUITE_BEGIN("robust");

TEST_CASE("the unit sphere seen from 1000 units away" *
          doctest::description("6. Far and grazing rays")) {
    const std::string graded = graded_forms({Form::float_rewrites}, {Form::textbook_float});
    for (const glm::vec3 o : {glm::vec3(600, -480, 640), glm::vec3(-3, 999, 40)}) {
        expect_accurate(shot(o, 0, 1), hits, why, graded);
        expect_accurate(shot(o, 0.6f, 1), hits, why, graded);
        expect_accurate(shot(o, 0.8f, 0.01f), hits, why, graded);
        expect_accurate(shot(o, 1.05f, 1), miss, why, graded);
    }
}

TEST_CASE("the unit sphere seen from 10000 units away" *
          doctest::description("6. Far and grazing rays")) {
    const std::string graded = graded_forms({Form::float_rewrites}, {Form::textbook_float});
    for (const glm::vec3 o : {glm::vec3(6000, -4800, 6400), glm::vec3(-30, 9999, 400)}) {
        expect_accurate(shot(o, 0, 1), hits, why, graded);
        expect_accurate(shot(o, 0.6f, 1), hits, why, graded);
        expect_accurate(shot(o, 0.8f, 4), hits, why, graded);
        expect_accurate(shot(o, 1.05f, 1), miss, why, graded);
    }
}

TEST_CASE("grazing rays near the silhouette of the unit sphere" *
          doctest::description("6. Far and grazing rays")) {
    const std::string graded = graded_forms({Form::float_rewrites}, {Form::textbook_float});
    // 1% inside and outside the radius, from 100 and 1000 units away.
    for (const glm::vec3 o : {glm::vec3(-96, 20, 25), glm::vec3(-960, 200, 250)}) {
        expect_accurate(shot(o, 0.99f, 1), hits, why, graded);
        expect_accurate(shot(o, 0.99f, 3), hits, why, graded);
        expect_accurate(shot(o, 1.01f, 1), miss, why, graded);
    }
}

TEST_SUITE_END();
