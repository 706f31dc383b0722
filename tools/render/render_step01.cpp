// Scenes of step 01: the unit sphere, drawn with intersect_unit_sphere and
// step 05's view_ray.
#include <limits>

#include <glm/geometric.hpp>

#include "raykit/render.hpp"
#include "raykit/unit_sphere.hpp"
#include "tool.hpp"

using namespace raykit;

namespace {

Canvas unit_sphere(const std::string& shading, int width, int height) {
    // Seen from a little above, so that the normals show the top of the sphere.
    const Camera camera = tool::look_at({0.0f, 1.2f, 3.3f}, {0, 0, 0}, {0, 1, 0}, 40.0f, width, height);
    const Color flat{0.95f, 0.55f, 0.15f};
    Canvas canvas(width, height);
    for (int j = 0; j < height; ++j) {
        for (int i = 0; i < width; ++i) {
            const Ray ray = view_ray(camera, i, j);  // step 05's
            const std::optional<float> t = intersect_unit_sphere(ray, 0.0f, std::numeric_limits<float>::infinity());
            if (!t) continue;
            // On the unit sphere the point is its own unit normal.
            canvas.at(i, j) = shading == "normals" ? tool::normal_color(glm::normalize(point_at(ray, *t))) : flat;
        }
    }
    return canvas;
}

}  // namespace

int main(int argc, char** argv) {
    return tool::run(argc, argv, {{"unit_sphere", {"flat", "normals"}, unit_sphere}});
}
