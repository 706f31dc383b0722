// Scenes of step 02: a few general spheres, drawn with intersect_sphere and
// step 05's view_ray.
// Built only when the kit has step 02 (tools/render/CMakeLists.txt).
#include <limits>

#include <glm/geometric.hpp>

#include "raykit/render.hpp"
#include "raykit/general_sphere.hpp"
#include "tool.hpp"

using namespace raykit;

namespace {

struct Ball {
    Sphere sphere;
    Color color;
};

Canvas spheres(const std::string& shading, int width, int height) {
    // A big sphere as the ground, and three that overlap on screen, so the
    // nearest one must win where they do.
    const Ball balls[] = {
        {{{0.3f, -41.0f, 0.0f}, 40.0f}, {0.55f, 0.55f, 0.5f}},
        {{{0.0f, 0.0f, 0.0f}, 1.0f}, {0.85f, 0.25f, 0.2f}},
        {{{1.3f, -0.4f, 1.3f}, 0.6f}, {0.2f, 0.45f, 0.9f}},
        {{{-1.25f, -0.5f, -1.4f}, 0.5f}, {0.3f, 0.75f, 0.3f}},
    };
    const Camera camera = tool::look_at({0.6f, 1.5f, 6.5f}, {0.0f, -0.4f, 0.0f}, {0, 1, 0}, 36.0f, width, height);
    Canvas canvas(width, height);
    for (int j = 0; j < height; ++j) {
        for (int i = 0; i < width; ++i) {
            const Ray ray = view_ray(camera, i, j);  // step 05's
            float nearest = std::numeric_limits<float>::infinity();
            const Ball* seen = nullptr;
            for (const Ball& b : balls) {
                const std::optional<float> t = intersect_sphere(ray, b.sphere, 0.0f, nearest);
                if (t && (seen == nullptr || *t < nearest)) {
                    nearest = *t;
                    seen = &b;
                }
            }
            if (seen == nullptr) continue;
            const glm::vec3 n = glm::normalize(point_at(ray, nearest) - seen->sphere.center);
            canvas.at(i, j) = shading == "normals" ? tool::normal_color(n) : seen->color;
        }
    }
    return canvas;
}

}  // namespace

int main(int argc, char** argv) {
    return tool::run(argc, argv, {{"spheres", {"flat", "normals"}, spheres}});
}
