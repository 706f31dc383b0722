// Step 01: the unit sphere at the origin.              <-- this file is yours
//
// Task:    steps/01_unit_sphere/README.md
// Lecture: lectures/01-unit-sphere.md
// Check:   ./kit check 1
//
// The declarations, with their full contract, are in
// include/raykit/unit_sphere.hpp (read it, do not edit it).
// Replace each `not_implemented_yet(...)` line with your code.

#include "raykit/unit_sphere.hpp"

#include <cmath>

#include <glm/geometric.hpp>

#include "raykit/not_implemented.hpp"

namespace raykit {

Roots unit_sphere_roots(const Ray& ray) {
    not_implemented_yet("unit_sphere_roots", ray);
}

std::optional<float> intersect_unit_sphere(const Ray& ray, float tmin, float tmax) {
    not_implemented_yet("intersect_unit_sphere", ray, tmin, tmax);
}

}  // namespace raykit
