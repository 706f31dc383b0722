// Step 05 grading suite, part 2: find_intersection, the closest hit over a
// list of objects (steps/05_cornell_box/render.cpp).
//
// The scenes are stacks of squares across the z axis and a ray along it, so
// every t is exact and each case is about the loop, not about geometry.

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

#include "cornell_checks.hpp"
#include "../support/relations.hpp"
#include "raykit/render.hpp"

using namespace raykit;
using namespace raykit::grading;

namespace {

// A 2 x 2 square across the z axis in the plane z = `z`, hit by the ray below.
Object square(const std::string& name, float z, float half = 1.0f) {
    return Object{name, Rect{2, z, {-half, -half}, {half, half}}, Color{0.5f, 0.5f, 0.5f}};
}

// A square beside the axis: the ray below passes it by.
Object aside(const std::string& name, float z) {
    return Object{name, Rect{2, z, {5, 5}, {6, 6}}, Color{0.5f, 0.5f, 0.5f}};
}

// From the origin along +z: it reaches the plane z = k at t = k.
const Ray along_z{{0, 0, 0}, {0, 0, 1}};

std::string named(const Scene& scene, std::size_t i) {
    return "[" + std::to_string(i) + "] \"" + scene.objects[i].name + "\"";
}

// What a wrong answer says about the loop, measured on it (issue 45: the words must fit the code, not a
// guess at it). A tie kept by the later object is read off the answer; it says which comparison each
// loop order needs, not which one the code has (both orders give the same answers). A hit expected at a
// negative t that was not returned: the function is asked again with that object alone in the same
// window; no hit there means it drops hits at a negative t; the hit there means it finds it but prefers
// another, and when that one is nearer the origin (|t| |d|) the words say so. Empty otherwise. The
// caller calls the function under test again afterwards, so the call the case records is the checked one.
std::string loop_cause(const Scene& scene, const Ray& ray, float tmin, float tmax, const std::optional<Hit>& expected,
                       const std::optional<Hit>& got) {
    // A skipped hit below a bound of the code's own (grading.hpp, own_epsilon), probed on a square z = 1 hit at
    // t along the direction (0, 0, 1/t).
    if (expected && (!got || got->t > expected->t)) {
        const std::string epsilon = epsilon_cause(
            tmin, tmax, std::optional<float>(expected->t), got ? std::optional<float>(got->t) : std::nullopt,
            [](float t) -> std::optional<float> {
                const std::optional<Hit> hit = find_intersection({{0, 0, 0}, {0, 0, 1 / t}}, Scene{{square("probe", 1)}}, 0, inf);
                return hit ? std::optional<float>(hit->t) : std::nullopt;
            });
        if (!epsilon.empty()) return epsilon;
    }
    if (expected && !got && expected->t < 0 && expected->index < scene.objects.size()) {
        // No hit where one lies behind the origin: the same object along the reversed ray, ahead of it.
        const Ray reversed{ray.origin, glm::vec3(0.0f) - ray.direction};
        const std::optional<Hit> ahead =
            find_intersection(reversed, Scene{{scene.objects[expected->index]}}, tmin, tmax);
        if (!ahead || !close(-expected->t, ahead->t)) return "";
        return " Measured on your answer: given the ray reversed, direction " + show(reversed.direction) + ", and " +
               named(scene, expected->index) + " alone, your function finds it at t = " + show(ahead->t) +
               ", ahead; along this ray it is at t = " + show(expected->t) + ", inside the window " + "[" +
               show(tmin) + ", " + show(tmax) + "], and your function finds no hit: it drops hits at a negative t.";
    }
    if (!expected || !got || got->index >= scene.objects.size()) return "";
    if (close(expected->t, got->t) && got->index > expected->index)
        return " Measured on your answer: " + named(scene, got->index) + " is hit at the same t = " + show(got->t) +
               " and is listed after " + named(scene, expected->index) + ": your function gives the tie to the "
               "object listed later. The one listed first must win: a loop from the first object to the last "
               "replaces the best only when strictly nearer (<, not <=); a loop from the last to the first must "
               "replace it on a tie too (<=).";
    if (!(expected->t < 0) || !(got->t > expected->t)) return "";
    const std::optional<Hit> alone = find_intersection(ray, Scene{{scene.objects[expected->index]}}, tmin, tmax);
    const std::string window = "[" + show(tmin) + ", " + show(tmax) + "]";
    if (!alone)
        return " Measured on your answer: with " + named(scene, expected->index) + " alone in the scene and the "
               "same window " + window + ", your function finds no hit, though the ray meets it at t = " +
               show(expected->t) + ", inside the window: it drops hits at a negative t. The window's tmin is the "
               "only lower bound; behind the origin is no reason to skip a hit.";
    if (!close(expected->t, alone->t)) return "";
    const float length = glm::length(ray.direction);
    std::string text = " Measured on your answer: with " + named(scene, expected->index) + " alone in the scene "
                       "your function finds it, at t = " + show(alone->t) + "; beside the others it returns t = " +
                       show(got->t) + " instead, a larger t.";
    if (std::fabs(got->t) < std::fabs(expected->t))
        text += " That hit is the nearer to the origin (|t| |d| = " + show(std::fabs(got->t) * length) + " against " +
                show(std::fabs(expected->t) * length) + "): your function chooses by distance from the origin, where "
                "the closest hit is the smallest t in the window, first along the ray.";
    return text;
}

// A relation every right answer keeps (relations.hpp's kind): the same objects listed in the reverse order
// change the index, never the t. Measured where loop_cause found nothing: the function asked again with
// the list reversed. Empty when the two t agree (or neither is a hit).
std::string order_cause(const Scene& scene, const Ray& ray, float tmin, float tmax, const std::optional<Hit>& got) {
    if (scene.objects.size() < 2 || !cheap_to_measure()) return "";
    Scene reversed = scene;
    std::reverse(reversed.objects.begin(), reversed.objects.end());
    const std::optional<Hit> other = find_intersection(ray, reversed, tmin, tmax);
    const bool same = got.has_value() == other.has_value() && (!got || close(got->t, other->t));
    if (same) return "";
    auto t_of = [](const std::optional<Hit>& h) { return h ? "t = " + show(h->t) : std::string("no hit"); };
    return " Measured on your function: the same objects listed in the reverse order give " + t_of(other) +
           ", where this order gives " + t_of(got) + ". The order of the list may change which index wins a tie, "
           "never the t: the closest hit is the smallest t in the window whatever the order, so compare each "
           "object's t with the best found so far.";
}

// Trial 9 (issue 54, s05_farthest_wins): each object asked alone gives its own t; the answer is the largest
// of them, in the list's order and in the reverse order alike, where the expected hit is the smallest: the
// comparison that keeps the best hit is reversed. Empty otherwise.
std::string farthest_cause(const Scene& scene, const Ray& ray, float tmin, float tmax, const std::optional<Hit>& expected,
                           const std::optional<Hit>& got) {
    if (!expected || !got || scene.objects.size() < 2 || !cheap_to_measure()) return "";
    float largest = -inf;
    int hits = 0;
    for (const Object& o : scene.objects) {
        const std::optional<Hit> alone = find_intersection(ray, Scene{{o}}, tmin, tmax);
        if (!alone) continue;
        ++hits;
        largest = std::max(largest, alone->t);
    }
    if (hits < 2 || !(largest > expected->t) || !close(got->t, largest)) return "";
    Scene reversed = scene;
    std::reverse(reversed.objects.begin(), reversed.objects.end());
    const std::optional<Hit> other = find_intersection(ray, reversed, tmin, tmax);
    if (!other || !close(other->t, largest)) return "";
    return " Measured on your function: it answers t = " + show(largest) + ", the farthest of the " +
           std::to_string(hits) + " hits (each object asked alone), in this order and with the list reversed "
           "alike, where the nearest, t = " + show(expected->t) + ", must win: your find_intersection keeps the "
           "largest t. The comparison is reversed: a new hit replaces the best only when its t is smaller (<, "
           "not >).";
}

void expect(const Scene& scene, const Ray& ray, float tmin, float tmax, std::optional<Hit> expected,
            const std::string& why) {
    std::optional<Hit> got = find_intersection(ray, scene, tmin, tmax);
    auto right = [&] {
        return expected.has_value() == got.has_value() &&
               (!expected || (got->index == expected->index && close(expected->t, got->t)));
    };
    if (!right()) {
        const std::string farthest = farthest_cause(scene, ray, tmin, tmax, expected, got);
        std::string measured = farthest.empty() ? loop_cause(scene, ray, tmin, tmax, expected, got) : "";
        if (farthest.empty() && measured.empty()) measured = order_cause(scene, ray, tmin, tmax, got);
        got = find_intersection(ray, scene, tmin, tmax);   // the call the case records
        FAIL_CHECK(report("find_intersection(ray, scene, tmin, tmax)",
                          show(ray) + ", window [" + show(tmin) + ", " + show(tmax) + "],\n            scene" +
                              show(scene),
                          show(expected), show(got),
                          farthest.empty() ? why + measured : with_fact(farthest, why)));
    }
}

void expect(const Scene& scene, std::optional<Hit> expected, const std::string& why) {
    expect(scene, along_z, 0.0f, inf, expected, why);
}

}  // namespace

TEST_SUITE_BEGIN("basic");

TEST_CASE("an empty scene is never hit" * doctest::description("4. The closest hit")) {
    expect(Scene{}, std::nullopt, "There is nothing to hit.");
}

TEST_CASE("one object: its t and index 0" * doctest::description("4. The closest hit")) {
    expect(Scene{{square("A", 3)}}, Hit{3, 0}, "The ray reaches z = 3 at t = 3; the only object has index 0.");
}

TEST_CASE("one object missed: no hit" * doctest::description("4. The closest hit")) {
    expect(Scene{{aside("A", 3)}}, std::nullopt, "The square lies beside the ray, which passes it by.");
}

TEST_CASE("two objects on one ray with the near one listed first" * doctest::description("4. The closest hit")) {
    expect(Scene{{square("near", 2), square("far", 5)}}, Hit{2, 0},
           "Both are hit (t = 2 and t = 5); the nearer, index 0, hides the other. A far object listed after a "
           "near one must not replace it: compare each t with the best so far, not with tmax.");
}

TEST_CASE("two objects on one ray with the near one listed last" * doctest::description("4. The closest hit")) {
    expect(Scene{{square("far", 5), square("near", 2)}}, Hit{2, 1},
           "Both are hit (t = 5 and t = 2); the nearer one wins wherever it is in the list: index 1.");
}

TEST_CASE("the nearest of three wins from the middle of the list" * doctest::description("4. The closest hit")) {
    expect(Scene{{square("far", 7), square("near", 3), square("middle", 5)}}, Hit{3, 1},
           "t = 7, 3 and 5: the smallest is 3, index 1. Keeping the last hit would give index 2.");
}

TEST_CASE("a far object after a near one and a nearer one after both" * doctest::description("4. The closest hit")) {
    expect(Scene{{square("B", 4), square("C", 6), square("A", 1)}}, Hit{1, 2},
           "t = 4, 6 and 1: the last is the nearest here, index 2. The loop must look at every object.");
}

TEST_CASE("a missed object listed last does not erase the hit" * doctest::description("4. The closest hit")) {
    expect(Scene{{square("hit", 3), aside("missed", 1)}}, Hit{3, 0},
           "The second square is nearer but beside the ray, so it is not hit: the best stays index 0.");
}

TEST_CASE("a tie goes to the object listed first" * doctest::description("4. The closest hit")) {
    expect(Scene{{square("small", 4, 1), square("big", 4, 2)}}, Hit{4, 0},
           "Both squares lie in z = 4 and are hit at t = 4. On a tie the object listed first wins.");
}

TEST_CASE("a tie goes to the object listed first in the other order too" *
          doctest::description("4. The closest hit")) {
    expect(Scene{{square("big", 4, 2), square("small", 4, 1)}}, Hit{4, 0},
           "Both are hit at t = 4: index 0 wins again, whichever object it is.");
}

TEST_CASE("a tie behind a nearer object" * doctest::description("4. The closest hit")) {
    expect(Scene{{square("A", 4), square("near", 2), square("B", 4)}}, Hit{2, 1},
           "t = 4, 2 and 4: the nearest is index 1, whatever happens between the two at t = 4.");
}

TEST_CASE("an object behind the origin is not seen" * doctest::description("4. The closest hit")) {
    expect(Scene{{square("behind", -3), square("ahead", 4)}}, Hit{4, 1},
           "z = -3 is met at t = -3, outside the window [0, inf]; the hit is the square ahead, at t = 4.");
}

TEST_CASE("a window with a negative part: the smallest t wins even behind the origin" *
          doctest::description("4. The closest hit")) {
    // The window [-5, inf] holds t = 2 and t = -3: the closest hit is the smallest t, -3, not the
    // one nearest the origin (|t| |d| = 2). Closest means first along the ray within the window.
    expect(Scene{{square("ahead", 2), square("behind", -3)}}, along_z, -5.0f, inf, Hit{-3, 1},
           "In the window [-5, inf] the ray meets z = -3 at t = -3 before z = 2 at t = 2: the smallest t "
           "wins, index 1.");
    expect(Scene{{square("far behind", -4), square("ahead", 1), square("behind", -2)}}, along_z, -3.0f, 10.0f,
           Hit{-2, 2}, "In the window [-3, 10]: t = -4 is before tmin, t = 1 and t = -2 are inside; the "
           "smallest, -2, wins: index 2.");
}

TEST_CASE("an object behind the origin alone is hit when the window reaches behind it" *
          doctest::description("4. The closest hit")) {
    // The negative-window case above without a hit ahead: a loop that drops a negative t (whatever tmin
    // says) fails here, choosing by distance from the origin does not (issue 45: told apart).
    expect(Scene{{square("behind", -3)}}, along_z, -5.0f, inf, Hit{-3, 0},
           "In the window [-5, inf] the ray meets z = -3 at t = -3, inside the window: a hit, behind the "
           "origin or not.");
}

TEST_CASE("an object very near the origin is hit: t = 2^-30" * doctest::description("4. The closest hit")) {
    // A hit at a small positive t: a loop with a lower bound of its own (t > 1e-4, against shadow acne)
    // fails here, one that drops only negative t does not (issue 45: told apart).
    expect(Scene{{square("near", 0x1p-30f)}}, along_z, 0.0f, inf, Hit{0x1p-30f, 0},
           "The ray meets z = 2^-30 at t = 2^-30, about 9.3e-10, inside the window [0, inf]: a hit, however "
           "small t is.");
}

TEST_CASE("an object before tmin is skipped for the next one" * doctest::description("4. The closest hit")) {
    expect(Scene{{square("near", 2), square("far", 5)}}, along_z, 3.0f, inf, Hit{5, 1},
           "t = 2 is before tmin = 3, so the nearest hit in the window is t = 5, index 1.");
}

TEST_CASE("objects after tmax are not hit" * doctest::description("4. The closest hit")) {
    expect(Scene{{square("near", 2), square("far", 5)}}, along_z, 0.0f, 1.0f, std::nullopt,
           "Both t = 2 and t = 5 are beyond tmax = 1.");
}

TEST_CASE("a hit exactly at tmax counts" * doctest::description("4. The closest hit")) {
    expect(Scene{{square("far", 5), square("near", 2)}}, along_z, 0.0f, 2.0f, Hit{2, 1},
           "The window is closed: t = tmax = 2 is a hit.");
}

TEST_CASE("a hit exactly at tmin counts" * doctest::description("4. The closest hit")) {
    expect(Scene{{square("near", 2), square("far", 5)}}, along_z, 5.0f, 9.0f, Hit{5, 1},
           "The window is closed: t = tmin = 5 is a hit, and t = 2 is before it.");
}

TEST_CASE("tmin greater than tmax is an empty window" * doctest::description("4. The closest hit")) {
    expect(Scene{{square("A", 2), square("B", 5)}}, along_z, 6.0f, 1.0f, std::nullopt,
           "No t satisfies 6 <= t <= 1.");
}

TEST_CASE("the hit's t counts steps of the ray's direction" * doctest::description("4. The closest hit")) {
    expect(Scene{{square("far", 6), square("near", 3)}}, Ray{{0, 0, 0}, {0, 0, 2}}, 0.0f, inf, Hit{1.5f, 1},
           "With d = (0, 0, 2) the plane z = 3 is 1.5 steps away: t = 1.5, as intersect_rect returns it.");
}

TEST_CASE("objects facing along different axes" * doctest::description("4. The closest hit")) {
    // A ray along (1, 1, 1) meets x = 3 at t = 3, y = 2 at t = 2 and z = 4 at t = 4.
    const Scene scene{{Object{"x = 3", Rect{0, 3, {0, 0}, {10, 10}}, Color{1, 0, 0}},
                       Object{"y = 2", Rect{1, 2, {0, 0}, {10, 10}}, Color{0, 1, 0}},
                       Object{"z = 4", Rect{2, 4, {0, 0}, {10, 10}}, Color{0, 0, 1}}}};
    expect(scene, Ray{{0, 0, 0}, {1, 1, 1}}, 0.0f, inf, Hit{2, 1},
           "The ray meets y = 2 first (t = 2), then x = 3 and z = 4.");
}

TEST_SUITE_END();
