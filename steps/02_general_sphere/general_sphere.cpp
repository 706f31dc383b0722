// Step 02: a sphere anywhere, of any size.             <-- this file is yours
//
// Task:    steps/02_general_sphere/README.md
// Lecture: lectures/02-general-sphere.md
// Check:   ./kit check 2
//
// The declarations, with their full contract, are in
// include/raykit/general_sphere.hpp (read it, do not edit it).
// Replace each `not_implemented_yet(...)` line with your code.

#include "raykit/general_sphere.hpp"

#include <cmath>

#include <glm/geometric.hpp>

#include "raykit/not_implemented.hpp"

namespace raykit {

Roots sphere_roots(const Ray& ray, const Sphere& sphere) {
    not_implemented_yet("sphere_roots", ray, sphere);
}

std::optional<float> intersect_sphere(const Ray& ray, const Sphere& sphere, float tmin, float tmax) {
    not_implemented_yet("intersect_sphere", ray, sphere, tmin, tmax);
}

}  // namespace raykit
