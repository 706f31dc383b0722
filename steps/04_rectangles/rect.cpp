// Step 04: axis-aligned rectangles.                    <-- this file is yours
//
// Task:    steps/04_rectangles/README.md
// Lecture: lectures/04-rectangles.md
// Check:   ./kit check 4
//
// The declaration, with its full contract, is in include/raykit/rect.hpp
// (read it, do not edit it). Replace the `not_implemented_yet(...)` line
// with your code.

#include "raykit/rect.hpp"

#include "raykit/not_implemented.hpp"

namespace raykit {

std::optional<float> intersect_rect(const Ray& ray, const Rect& rect, float tmin, float tmax) {
    not_implemented_yet("intersect_rect", ray, rect, tmin, tmax);
}

}  // namespace raykit
