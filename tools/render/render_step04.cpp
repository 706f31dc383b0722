// Scenes of step 04: rectangles facing all three axes, drawn by step 05's
// render loop (view_ray, find_intersection) on top of step 04's intersect_rect:
// the tool itself computes no view ray and no closest hit (tool.hpp).
#include "raykit/render.hpp"
#include "tool.hpp"

using namespace raykit;

namespace {

Canvas rectangles(const std::string&, int width, int height) {
    // None of them square, so a student's swapped (u, v) shows as a wrong
    // shape; the card floats in front of the back panel, so the nearest must win.
    const Scene scene{{
        {"floor", Rect{1, 0.0f, {-2.0f, -3.0f}, {2.0f, 1.0f}}, {0.6f, 0.6f, 0.6f}},   // y = 0, (x, z)
        {"back", Rect{2, -3.0f, {-2.0f, 0.0f}, {1.0f, 2.5f}}, {0.2f, 0.4f, 0.85f}},  // z = -3, (x, y)
        {"side", Rect{0, -2.0f, {0.0f, -3.0f}, {1.5f, 0.0f}}, {0.9f, 0.5f, 0.15f}},  // x = -2, (y, z)
        {"card", Rect{2, -0.8f, {-0.6f, 0.9f}, {0.6f, 1.5f}}, {0.95f, 0.85f, 0.2f}},  // z = -0.8, (x, y)
        {"fin", Rect{0, 1.2f, {0.0f, -2.4f}, {1.0f, -0.6f}}, {0.7f, 0.2f, 0.5f}},   // x = 1.2, (y, z)
    }};
    return render(scene, tool::look_at({3.4f, 2.2f, 3.6f}, {-0.3f, 0.8f, -1.2f}, {0, 1, 0}, 45.0f, width, height));
}

}  // namespace

int main(int argc, char** argv) { return tool::run(argc, argv, {{"rectangles", {"flat"}, rectangles}}); }
