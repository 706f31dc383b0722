// Intel Embree 3 or 4 on the benchmark's scenes, for comparison: the box as quads,
// a sphere as one sphere point, each built once, traced with rtcIntersect1.
// Optional: without Embree (RAYKIT_BENCH_EMBREE = 0) available() is false and
// status() says why.
#pragma once

#include <string>
#include <vector>

#include "box.hpp"
#include "vec.hpp"

namespace raykit::bench::embree {

bool available();
/// "Embree 3.13.5" (or 4.x), or why Embree is not used.
std::string status();

/// A committed Embree scene; owned by the module, alive to the end.
struct Scene;

/// The rectangles as quads, one geometry; primID is the rectangle's index.
const Scene* quads(const std::vector<Rect3>& rects);
/// One sphere point (RTC_GEOMETRY_TYPE_SPHERE_POINT).
const Scene* sphere(const Vec3<float>& centre, float radius);

/// The closest hit in [tmin, inf): rtcIntersect1 with tfar = inf.
BoxHit intersect(const Scene* scene, const Vec3<float>& o, const Vec3<float>& d, float tmin);

}  // namespace raykit::bench::embree
