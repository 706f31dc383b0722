// Many rays at once: the formulations of lanes-inl.h on Google Highway's
// vectors, over rays stored as a structure of arrays, for every instruction
// set this CPU runs that the build compiled (vector.cpp). Optional: without
// Highway (RAYKIT_BENCH_HWY = 0) targets() is empty and status() says why.
#pragma once

#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include "box.hpp"
#include "vec.hpp"

namespace raykit::bench::simd {

/// Rays and spheres as a structure of arrays: one array per coordinate, so
/// that one vector load fetches the same coordinate of 8 or 16 rays. Padded
/// to a multiple of kPad by repeating the last ray.
struct Rays {
    std::vector<float> ox, oy, oz, dx, dy, dz, cx, cy, cz, r;
    std::size_t n = 0;  ///< real rays, before the padding
};

/// Wide enough for any vector (AVX-512: 16 floats).
constexpr std::size_t kPad = 16;

Rays to_lanes(const std::vector<Sample<float>>& samples);

/// Roots of rays [begin, end) (multiples of kPad) into t0, t1 and hit (2 for a
/// hit, 0 for a miss; roots 0 on a miss).
///
/// A kernel with double lanes widens each of the ten float arrays it reads and
/// narrows each of the three it writes: kConversions per ray, which the flop
/// count does not see but the roofline must (docs/bench.md, section 6).
constexpr int kInputs = 10, kOutputs = 3, kConversions = kInputs + kOutputs;
using SphereKernel = void (*)(const Rays& in, std::size_t begin, std::size_t end, float* t0, float* t1,
                              float* hit);

/// Rays into a table of rectangles, as a structure of arrays (origins and
/// directions only), padded like Rays.
struct BoxRays {
    std::vector<float> ox, oy, oz, dx, dy, dz;
    std::size_t n = 0;
};

BoxRays to_lanes(const std::vector<Vec3<float>>& o, const std::vector<Vec3<float>>& d);

/// The closest hit of rays [begin, end) over `n` rectangles in [tmin, inf):
/// t (0 on a miss) and the rectangle's index as a float (-1 on a miss).
using BoxKernel = void (*)(const BoxRays& in, std::size_t begin, std::size_t end, const Rect3* rects, int n,
                           float tmin, float* t, float* rect);

/// One instruction set's kernels and its measured limits.
struct Target {
    std::string name;            ///< Highway's name: "AVX2", "AVX3", "AVX3_DL", ...
    int lanes_f32 = 0, lanes_f64 = 0;
    SphereKernel half_b_f32 = nullptr, stable_f32 = nullptr, exact_f32 = nullptr;  ///< float lanes
    SphereKernel half_b_f64 = nullptr, lagrange_f64 = nullptr;  ///< float in, double lanes inside
    BoxKernel box_f32 = nullptr;
    /// One core's rates with these vectors, measured by measure(): fused
    /// multiply-adds (two flops each), and the time per lane of a divide and
    /// of a square root when many are in flight.
    double gflops_f32 = 0, gflops_f64 = 0;
    double div_ns_f32 = 0, div_ns_f64 = 0, sqrt_ns_f32 = 0, sqrt_ns_f64 = 0;
    /// The time per lane of one conversion between float and double (a
    /// widening or a narrowing, measured in pairs) when many are in flight:
    /// the double lanes on float rays pay one per input and per result.
    double cvt_ns = 0;
    /// What a loop of two kernels adds of the shorter one's time to the
    /// longer one's (0: they run beside each other, 1: they take turns):
    /// fused multiply-adds with conversions, divides with square roots (in
    /// double lanes). NaN until measured.
    double shared_fma_cvt = std::numeric_limits<double>::quiet_NaN();
    double shared_div_sqrt = std::numeric_limits<double>::quiet_NaN();
    /// The peak kernels measure() runs (vector.cpp: which kernel, iterations, seed).
    double (*kernels)(int kernel, long iterations, double seed) = nullptr;
};

/// The best instruction set for this CPU (Highway's dynamic dispatch) first,
/// then AVX2 when the best one is wider; empty without Highway.
std::vector<Target> targets();

/// Measures t's rates: `repetitions` runs of about `seconds`, the best.
void measure(Target& t, double seconds, int repetitions);

/// "Highway 1.0.3", or why the vector rows are skipped.
std::string status();

}  // namespace raykit::bench::simd
