// Reference solution for step 05: the empty Cornell box.
// Lecture: lectures/05-cornell-box.md, sections 2 and 3.
//
// Numbers from the Cornell box data, Cornell University Program of Computer
// Graphics (https://www.graphics.cornell.edu/online/box/data.html), in mm.
// The measured walls are not quite square to each other (the red wall leans
// by up to 6.4 mm); each wall is put in the plane through its outermost
// measured corner, so the box is x in [0, 556], y in [0, 548.8],
// z in [0, 559.2], open at z = 0 where the camera looks in.

#include "raykit/cornell_box.hpp"
#include "raykit/scenes/cornell_box_data.hpp"

namespace raykit {

namespace {

constexpr float width = 556.0f;   // x: the green wall is at 0, the red one here
constexpr float height = 548.8f;  // y: the floor is at 0, the ceiling here
constexpr float depth = 559.2f;   // z: the open front is at 0, the back wall here

// Flat colours: each measured reflectance spectrum averaged over the blue
// (400-496 nm), green (500-596 nm) and red (600-700 nm) thirds of the data.
// They, and the camera, are read from the scene file that the suites, the
// renderer and lecture 05's tables read too (include/raykit/scenes/
// cornell_box.inc): a changed colour is one edit there. The geometry stays
// written out below, as a student transcribes it from the lecture's table.
const Color& white = scenes::cornell::white;
const Color& red = scenes::cornell::red;
const Color& green = scenes::cornell::green;
const Color& light_color = scenes::cornell::light;

}  // namespace

Scene cornell_box() {
    Scene scene;
    // The light first: it lies in the ceiling's plane, so both are hit at the
    // same t, and on a tie the object listed first is seen.
    scene.objects.push_back({"light", Rect{1, height, {213.0f, 227.0f}, {343.0f, 332.0f}}, light_color});
    scene.objects.push_back({"floor", Rect{1, 0.0f, {0.0f, 0.0f}, {width, depth}}, white});
    scene.objects.push_back({"ceiling", Rect{1, height, {0.0f, 0.0f}, {width, depth}}, white});
    scene.objects.push_back({"back wall", Rect{2, depth, {0.0f, 0.0f}, {width, height}}, white});
    scene.objects.push_back({"left wall", Rect{0, width, {0.0f, 0.0f}, {height, depth}}, red});
    scene.objects.push_back({"right wall", Rect{0, 0.0f, {0.0f, 0.0f}, {height, depth}}, green});
    return scene;
}

Camera cornell_camera(int width_px, int height_px) {
    // Position 278 273 -800, direction 0 0 1, up 0 1 0, focal length 0.035,
    // film 0.025 x 0.025 (metres; only their ratio matters).
    return scenes::cornell::camera(width_px, height_px);
}

}  // namespace raykit
