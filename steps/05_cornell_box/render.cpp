// Step 05: the closest hit, view rays, the render loop.  <-- this file is yours
//
// Task:    steps/05_cornell_box/README.md
// Lecture: lectures/05-cornell-box.md (sections 4 to 7)
// Check:   ./kit check 5        See it: ./kit render cornell_box --steps steps
//
// The declarations, with their full contracts, are in
// include/raykit/render.hpp; the types they use in scene.hpp and camera.hpp
// (read them, do not edit them). Replace each `not_implemented_yet(...)` line
// with your code.

#include "raykit/render.hpp"

#include <limits>

#include <glm/geometric.hpp>

#include "raykit/not_implemented.hpp"

namespace raykit {

std::optional<Hit> find_intersection(const Ray& ray, const Scene& scene, float tmin, float tmax) {
    not_implemented_yet("find_intersection", ray, scene, tmin, tmax);
}

Ray view_ray(const Camera& camera, int i, int j) {
    not_implemented_yet("view_ray", camera, i, j);
}

Canvas render(const Scene& scene, const Camera& camera) {
    not_implemented_yet("render", scene, camera);
}

}  // namespace raykit
