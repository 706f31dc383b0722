// Scenes of step 04: rectangles facing all three axes, drawn with
// intersect_rect and step 05's view_ray.
#include <limits>

#include "raykit/camera.hpp"
#include "raykit/rect.hpp"
#include "tool.hpp"

using namespace raykit;

namespace {

struct Panel {
    Rect rect;
    Color color;
};

Canvas rectangles(const std::string&, int width, int height) {
    // None of them square, so a student's swapped (u, v) shows as a wrong
    // shape; the card floats in front of the back panel, so the nearest must win.
    const Panel panels[] = {
        {Rect{1, 0.0f, {-2.0f, -3.0f}, {2.0f, 1.0f}}, {0.6f, 0.6f, 0.6f}},   // floor y = 0, (x, z)
        {Rect{2, -3.0f, {-2.0f, 0.0f}, {1.0f, 2.5f}}, {0.2f, 0.4f, 0.85f}},  // back z = -3, (x, y)
        {Rect{0, -2.0f, {0.0f, -3.0f}, {1.5f, 0.0f}}, {0.9f, 0.5f, 0.15f}},  // side x = -2, (y, z)
        {Rect{2, -0.8f, {-0.6f, 0.9f}, {0.6f, 1.5f}}, {0.95f, 0.85f, 0.2f}},  // card z = -0.8, (x, y)
        {Rect{0, 1.2f, {0.0f, -2.4f}, {1.0f, -0.6f}}, {0.7f, 0.2f, 0.5f}},   // fin x = 1.2, (y, z)
    };
    const Camera camera = tool::look_at({3.4f, 2.2f, 3.6f}, {-0.3f, 0.8f, -1.2f}, {0, 1, 0}, 45.0f, width, height);
    Canvas canvas(width, height);
    for (int j = 0; j < height; ++j) {
        for (int i = 0; i < width; ++i) {
            const Ray ray = view_ray(camera, i, j);  // step 05's
            float nearest = std::numeric_limits<float>::infinity();
            const Panel* seen = nullptr;
            for (const Panel& p : panels) {
                const std::optional<float> t = intersect_rect(ray, p.rect, 0.0f, nearest);
                if (t && (seen == nullptr || *t < nearest)) {
                    nearest = *t;
                    seen = &p;
                }
            }
            if (seen != nullptr) canvas.at(i, j) = seen->color;
        }
    }
    return canvas;
}

}  // namespace

int main(int argc, char** argv) { return tool::run(argc, argv, {{"rectangles", {"flat"}, rectangles}}); }
