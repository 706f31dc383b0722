// Step 03: the unit-direction shortcut and its geometric reading.   <-- this file is yours
//
// Task:    steps/03_unit_direction/README.md
// Lecture: lectures/03-unit-direction.md
// Check:   ./kit check 3
//
// The declarations, with their full contract, are in
// include/raykit/unit_direction.hpp (read it, do not edit it).
// Replace each `not_implemented_yet(...)` line with your code.

#include "raykit/unit_direction.hpp"

#include <cmath>

#include <glm/geometric.hpp>

#include "raykit/not_implemented.hpp"

namespace raykit {

Roots sphere_roots_unit_dir(const Ray& ray, const Sphere& sphere) {
    not_implemented_yet("sphere_roots_unit_dir", ray, sphere);
}

Roots sphere_roots_geometric(const Ray& ray, const Sphere& sphere) {
    not_implemented_yet("sphere_roots_geometric", ray, sphere);
}

}  // namespace raykit
