// The kit's own code as benchmark subjects: the step libraries of the build
// this program is part of (solutions/ in the reference build, the student's
// steps/ in the student build). Each function is compiled in or reported
// absent, depending on which steps the build has; see bench/CMakeLists.txt.
#pragma once

#include <string>
#include <vector>

#include "raykit/ray.hpp"
#include "raykit/roots.hpp"
#include "raykit/sphere.hpp"

#include "box.hpp"

namespace raykit::bench::kit {

/// Which step the sphere subject calls: 2 (step 02's sphere_roots), 1 (step
/// 01's unit_sphere_roots, after moving the ray into the sphere's frame) or 0
/// (neither is built: no subject).
int sphere_step();

/// The kit's roots of `ray` with `sphere`, through sphere_step()'s function.
Roots sphere_roots(const Ray& ray, const Sphere& sphere);

/// Step 04's intersect_rect is built in.
bool has_rect();
/// Step 05's cornell_box() and find_intersection() are built in.
bool has_scene();

/// The Cornell box the benchmark uses: step 05's cornell_box() when it is
/// built in (so every variant sees the kit's scene), the benchmark's own table
/// otherwise. Throws whatever cornell_box() throws (a stub's not_implemented).
std::vector<Rect3> box_table();

/// A table of rectangles in step 04's type, made once.
struct RectTable;
const RectTable* rect_table(const std::vector<Rect3>& rects);

/// The closest hit over a table, one intersect_rect call per rectangle, in
/// [tmin, inf). Requires has_rect().
BoxHit brute_force(const RectTable* table, const Ray& ray, float tmin);

/// find_intersection over cornell_box() in [tmin, inf). Requires has_scene().
BoxHit find_intersection(const Ray& ray, float tmin);

}  // namespace raykit::bench::kit
