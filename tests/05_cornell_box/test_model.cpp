// Step 05 grading suite, part 1: the model of the empty Cornell box and its
// camera (steps/05_cornell_box/cornell_box.cpp).
//
// The numbers are those of lecture 05, sections 2 and 3: the Cornell box data
// (Cornell University Program of Computer Graphics), with each wall moved to
// the axis-aligned plane through its outermost measured corner.

#include <doctest/doctest.h>

#include <algorithm>

#include "cornell_checks.hpp"
#include "raykit/cornell_box.hpp"
#include "raykit/scenes/cornell_box_data.hpp"

using namespace raykit;
using namespace raykit::grading;

namespace {

// The colours of include/raykit/scenes/cornell_box.inc, the one place the box's numbers live.
using scenes::cornell::white;
using scenes::cornell::red;
using scenes::cornell::green;
using scenes::cornell::light;

// Positions are typed in from a table: equal to float precision.
bool same(float expected, float got) { return close(expected, got); }

const Object* find(const Scene& scene, const std::string& name) {
    const Object* found = nullptr;
    for (const Object& o : scene.objects) {
        if (o.name == name) found = &o;
    }
    return found;
}

// Checks one object of cornell_box(): that it exists, where it is, and its colour.
void expect_object(const std::string& name, const Rect& rect, const Color& color, const std::string& why) {
    const Scene scene = cornell_box();
    const Object* o = find(scene, name);
    if (o == nullptr) {
        FAIL_CHECK(report("cornell_box()", "", "an object named \"" + name + "\"",
                          "the objects" + show(scene), "Name the six objects exactly as the header says."));
        return;
    }
    const Rect& r = o->shape;
    const bool where = r.axis == rect.axis && same(rect.offset, r.offset) && same(rect.lo.x, r.lo.x) &&
                       same(rect.lo.y, r.lo.y) && same(rect.hi.x, r.hi.x) && same(rect.hi.y, r.hi.y);
    if (!where) {
        FAIL_CHECK(report("cornell_box(), object \"" + name + "\"", "", show(rect), show(r), why));
    }
    if (!same_color(color, o->color)) {
        FAIL_CHECK(report("cornell_box(), object \"" + name + "\"", "", "color " + show(color),
                          "color " + show(o->color),
                          "Lecture 05, section 3, gives each surface's colour (averages of the measured spectra)."));
    }
}

// What a ray from `from` along `direction` sees first, checked with the
// suite's own closest-hit loop (ties to the object listed first).
void expect_seen(const glm::vec3& from, const glm::vec3& direction, const char* expected,
                 const std::string& why) {
    const Scene scene = cornell_box();
    const Ray ray{from, direction};
    const Object* seen = first_seen(scene, ray);
    const std::string got = seen ? "\"" + seen->name + "\"" : "nothing";
    const std::string want = expected ? "\"" + std::string(expected) + "\"" : "nothing";
    if (got != want) {
        FAIL_CHECK(report("the first object of cornell_box() hit by a ray (found with your intersect_rect)",
                          show(ray), want, got, why));
    }
}

// The middle of the box, right under the middle of the light.
const glm::vec3 middle{278.0f, 274.4f, 279.6f};

}  // namespace

TEST_SUITE_BEGIN("basic");

TEST_CASE("the box holds six objects with the six names" * doctest::description("3. The model as six rectangles")) {
    const Scene scene = cornell_box();
    const char* names[] = {"floor", "ceiling", "back wall", "left wall", "right wall", "light"};
    std::string problems;
    for (const char* name : names) {
        const auto n = std::count_if(scene.objects.begin(), scene.objects.end(),
                                     [&](const Object& o) { return o.name == name; });
        if (n != 1) problems += " \"" + std::string(name) + "\" appears " + std::to_string(n) + " times.";
    }
    if (scene.objects.size() != 6) problems += " There are " + std::to_string(scene.objects.size()) + " objects.";
    if (!problems.empty()) {
        FAIL_CHECK(report("cornell_box()", "", "six objects: floor, ceiling, back wall, left wall, right wall, light",
                          "the objects" + show(scene),
                          problems.substr(1) + " The empty box is these six rectangles, each once, nothing else."));
    }
}

TEST_CASE("the floor is the plane y = 0 across the whole box" *
          doctest::description("3. The model as six rectangles")) {
    expect_object("floor", Rect{1, 0.0f, {0, 0}, {556.0f, 559.2f}}, white,
                  "The floor is y = 0 (axis 1), with (x, z) from (0, 0) to (556, 559.2): the box's width and depth.");
}

TEST_CASE("the ceiling is the plane y = 548.8" * doctest::description("3. The model as six rectangles")) {
    expect_object("ceiling", Rect{1, 548.8f, {0, 0}, {556.0f, 559.2f}}, white,
                  "The ceiling is y = 548.8 (axis 1), with (x, z) from (0, 0) to (556, 559.2).");
}

TEST_CASE("the back wall is the plane z = 559.2" * doctest::description("3. The model as six rectangles")) {
    expect_object("back wall", Rect{2, 559.2f, {0, 0}, {556.0f, 548.8f}}, white,
                  "The back wall is z = 559.2 (axis 2), with (x, y) from (0, 0) to (556, 548.8).");
}

TEST_CASE("the red left wall is the plane x = 556" * doctest::description("3. The model as six rectangles")) {
    expect_object("left wall", Rect{0, 556.0f, {0, 0}, {548.8f, 559.2f}}, red,
                  "The red wall is x = 556 (axis 0: the outermost measured x), with (y, z) from (0, 0) to "
                  "(548.8, 559.2). Seen from the camera at z = -800 looking along +z, +x is on the left.");
}

TEST_CASE("the green right wall is the plane x = 0" * doctest::description("3. The model as six rectangles")) {
    expect_object("right wall", Rect{0, 0.0f, {0, 0}, {548.8f, 559.2f}}, green,
                  "The green wall is x = 0 (axis 0), with (y, z) from (0, 0) to (548.8, 559.2).");
}

TEST_CASE("the light is a 130 by 105 mm rectangle in the ceiling" *
          doctest::description("3. The model as six rectangles")) {
    expect_object("light", Rect{1, 548.8f, {213.0f, 227.0f}, {343.0f, 332.0f}}, light,
                  "The light is y = 548.8 (axis 1), x from 213 to 343 and z from 227 to 332 (130 x 105 mm).");
}

TEST_CASE("looking up from the middle of the box you see the light" *
          doctest::description("3. The model as six rectangles")) {
    expect_seen(middle, {0, 1, 0}, "light",
                "The light is right above the middle of the box, in the ceiling's plane: both are hit at "
                "the same t, and the object listed first wins the tie. List the light before the ceiling.");
}

TEST_CASE("looking up beside the light you see the ceiling" *
          doctest::description("3. The model as six rectangles")) {
    expect_seen({100, 274.4f, 100}, {0, 1, 0}, "ceiling", "Above (x, z) = (100, 100) there is ceiling, not light.");
}

TEST_CASE("looking down from the middle of the box you see the floor" *
          doctest::description("3. The model as six rectangles")) {
    expect_seen(middle, {0, -1, 0}, "floor", "Straight down from the middle is the floor y = 0.");
}

TEST_CASE("looking towards +x from the middle you see the red wall" *
          doctest::description("3. The model as six rectangles")) {
    expect_seen(middle, {1, 0, 0}, "left wall", "Along +x the ray meets the red wall x = 556.");
}

TEST_CASE("looking towards -x from the middle you see the green wall" *
          doctest::description("3. The model as six rectangles")) {
    expect_seen(middle, {-1, 0, 0}, "right wall", "Along -x the ray meets the green wall x = 0.");
}

TEST_CASE("looking towards +z from the middle you see the back wall" *
          doctest::description("3. The model as six rectangles")) {
    expect_seen(middle, {0, 0, 1}, "back wall", "Along +z the ray meets the back wall z = 559.2.");
}

TEST_CASE("looking out of the open front you see nothing" *
          doctest::description("3. The model as six rectangles")) {
    expect_seen(middle, {0, 0, -1}, nullptr, "The box is open at z = 0, where the camera looks in: no front wall.");
}

TEST_CASE("a ray aimed exactly at the edge where the floor meets the red wall hits one of them" *
          doctest::description("3. The model as six rectangles")) {
    // Both planes are reached at exactly t = 1, at (556, 0, 400): a tie,
    // which either object may win depending on the order of the list.
    const Scene scene = cornell_box();
    const Ray ray{middle, glm::vec3{556.0f, 0.0f, 400.0f} - middle};
    const Object* seen = first_seen(scene, ray);
    if (seen == nullptr || (seen->name != "floor" && seen->name != "left wall")) {
        FAIL_CHECK(report("the first object of cornell_box() hit by a ray (found with your intersect_rect)",
                          show(ray), "\"floor\" or \"left wall\"", seen ? "\"" + seen->name + "\"" : "nothing",
                          "The walls must meet along their edges, with no gap: the floor reaches x = 556 and the "
                          "red wall reaches down to y = 0."));
    }
}

TEST_CASE("the camera is the one of the Cornell box data" * doctest::description("2. The Cornell box data")) {
    const Camera c = cornell_camera(64, 48);
    const Camera want = scenes::cornell::camera(64, 48);
    const bool ok = same(want.eye.x, c.eye.x) && same(want.eye.y, c.eye.y) && same(want.eye.z, c.eye.z) &&
                    same(want.forward.x, c.forward.x) && same(want.forward.y, c.forward.y) &&
                    same(want.forward.z, c.forward.z) && same(want.up.x, c.up.x) && same(want.up.y, c.up.y) &&
                    same(want.up.z, c.up.z) &&
                    std::fabs(c.film_height / c.focal_length - want.film_height / want.focal_length) < 1e-5f &&
                    c.width == 64 && c.height == 48;
    if (!ok) {
        FAIL_CHECK(report("cornell_camera(64, 48)", "", show(want), show(c),
                          "Position 278 273 -800, direction 0 0 1, up 0 1 0, focal length 0.035, film 0.025 high, "
                          "and the image size asked for. (Any unit for the film will do if the ratio is the same.)"));
    }
}

TEST_SUITE_END();
