// Step 05 grading suite, ★ robust tier: the two bugs of the closest-hit
// sketch in lecture 05, section 9 ("spot the bugs").
//
// The sketch tests the object instead of its hit, so every object replaces
// the answer, and it keeps a name (`surf`) that the loop never sets, so the
// answer does not name the object just tested. Transcribed as it stands, it
// returns an object for a ray that hits nothing, and always the same index.
// The basic cases of test_closest_hit.cpp catch both too; these say which.

#include <doctest/doctest.h>

#include <limits>
#include <string>

#include "cornell_checks.hpp"
#include "raykit/render.hpp"
#include "raykit/scenes/cornell_box_data.hpp"

using namespace raykit;
using namespace raykit::grading;

namespace {

// The empty Cornell box as lecture 05 section 3 tabulates it (include/raykit/scenes/cornell_box.inc),
// built here so that these cases depend on find_intersection alone, not on cornell_box().
Scene box() {
    Scene scene;
    for (const scenes::cornell::Row& row : scenes::cornell::rows()) scene.objects.push_back({row.name, row.rect, row.color});
    return scene;
}

// Why the answer is wrong, read off the answer itself: with the right t but another object, is that
// object hit at the same t too (asked of your own find_intersection, on a scene of that object alone)?
// Then it is a tie kept by the object listed later; if not, the index does not belong to the hit found.
std::string cause(const Scene& scene, const Ray& ray, const std::optional<Hit>& expected,
                  const std::optional<Hit>& got) {
    if (!expected || !got || !close(expected->t, got->t) || got->index == expected->index) return "";
    if (got->index >= scene.objects.size()) return " The index is not one of the scene's objects.";
    const std::optional<Hit> alone = find_intersection(ray, Scene{{scene.objects[got->index]}}, 0.0f, inf);
    const std::string other = scene.objects[got->index].name + " (index " + std::to_string(got->index) + ")";
    if (alone && close(expected->t, alone->t))
        return " Measured on your answer: " + other + " is hit at the same t, and it is listed after " +
               scene.objects[expected->index].name + ": a tie, kept by the later object. On a tie the object "
               "listed first wins (lecture 05, section 4).";
    return " Measured on your answer: " + other + " is not hit at this t" +
           (alone ? " (alone, it is hit at t = " + show(alone->t) + ")" : std::string(" (alone, it is not hit at all)")) +
           ", so the index returned is not the one of the hit found: a variable the loop does not set with the "
           "hit (lecture 05, section 9, bug 2).";
}

void expect(const Scene& scene, const Ray& ray, std::optional<Hit> expected, const std::string& why) {
    const std::optional<Hit> got = find_intersection(ray, scene, 0.0f, inf);
    const bool ok = expected.has_value() == got.has_value() &&
                    (!expected || (got->index == expected->index && close(expected->t, got->t)));
    if (!ok) {
        const std::string measured = cause(scene, ray, expected, got);
        FAIL_CHECK(report("find_intersection(ray, scene, 0, inf)", show(ray) + ",\n            scene" + show(scene),
                          show(expected), show(got), measured.empty() ? why : why + measured));
    }
}

}  // namespace

TEST_SUITE_BEGIN("robust");

TEST_CASE("a ray that misses every object of the box gets no object" *
          doctest::description("9. Spot the bugs in a closest-hit sketch")) {
    // From the middle of the box out through its open front (z = 0), and
    // from in front of the box away from it: no wall is in the window.
    expect(box(), Ray{{278, 273, 300}, {0, 0, -1}}, std::nullopt,
           "The ray leaves through the open front: nothing is hit, so no object may be returned. A loop "
           "that tests the object instead of its hit returns the last object listed (lecture 05, section 9, "
           "bug 1).");
    expect(box(), Ray{{278, 273, -800}, {0.1f, 0.2f, -1}}, std::nullopt,
           "The ray points away from the box: nothing is hit, so no object may be returned.");
}

TEST_CASE("the hit names the object it belongs to wherever it is listed" *
          doctest::description("9. Spot the bugs in a closest-hit sketch")) {
    // From the eye of the Cornell camera: one ray per wall, each hitting
    // only that wall first. Index 0 (the light) and the last index (the right
    // wall) are among them, so a constant index fails somewhere.
    const Scene scene = box();
    const glm::vec3 eye{278, 273, -800};
    struct Aim { const char* what; glm::vec3 target; std::size_t index; };
    const Aim aims[] = {{"the light", {278, 548.8f, 279.5f}, 0},  {"the floor", {278, 0, 300}, 1},
                        {"the ceiling", {100, 548.8f, 100}, 2}, {"the back wall", {278, 273, 559.2f}, 3},
                        {"the left wall", {556, 273, 300}, 4},  {"the right wall", {0, 273, 300}, 5}};
    for (const Aim& aim : aims) {
        const Ray ray{eye, aim.target - eye};
        expect(scene, ray, Hit{1, aim.index},
               std::string("The ray from the eye is aimed at ") + aim.what + ", reached at t = 1, index " +
                   std::to_string(aim.index) + ": the answer must name the object whose hit it returns.");
    }
}

TEST_SUITE_END();
