// Intel Embree 3 or 4 on the benchmark's scenes, for comparison: the box as quads,
// a sphere as one sphere point, each built once, traced with rtcIntersect1.
// Optional: without Embree (RAYKIT_BENCH_EMBREE = 0) available() is false and
// status() says why.
#pragma once

#include <cstddef>
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

/// Whether this Embree runs packets of `width` rays (8 or 16) natively.
bool packets(int width);

/// The closest hits of rays [begin, end) (a multiple of `width`), given as a
/// structure of arrays, `width` at a time: rtcIntersect8 or rtcIntersect16.
/// t is 0 and rect -1 on a miss.
void intersect_packets(const Scene* scene, int width, const float* const o[3], const float* const d[3],
                       std::size_t begin, std::size_t end, float tmin, float* t, float* rect);

}  // namespace raykit::bench::embree
