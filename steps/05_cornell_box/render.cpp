// Step 05: the closest hit, view rays, the render loop.  <-- this file is yours
//
// Task:    steps/05_cornell_box/README.md
// Lecture: lectures/05-cornell-box.md (sections 4 to 7)
// Check:   ./kit check 5        See it: ./kit render cornell_box --steps steps
//
// The declarations, with their full contracts, are in include/raykit/scene.hpp,
// include/raykit/camera.hpp and include/raykit/render.hpp (read them, do not
// edit them). Replace each `not_implemented_yet(...)` line with your code.

#include "raykit/render.hpp"

#include <limits>

#include <glm/geometric.hpp>

#include "raykit/not_implemented.hpp"

namespace raykit {

std::optional<Hit> find_intersection(const Ray& ray, const Scene& scene, float tmin, float tmax) {
    (void)ray;
    (void)scene;
    (void)tmin;
    (void)tmax;
    not_implemented_yet("find_intersection");
}

Ray view_ray(const Camera& camera, int i, int j) {
    (void)camera;
    (void)i;
    (void)j;
    not_implemented_yet("view_ray");
}

Canvas render(const Scene& scene, const Camera& camera) {
    (void)scene;
    (void)camera;
    not_implemented_yet("render");
}

}  // namespace raykit
