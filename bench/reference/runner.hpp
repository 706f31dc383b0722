// What the benchmark's pieces share: the rays of each family with their exact
// answers, the variants under test, and what the error pass, the timing and
// the JSON writer exchange. main.cpp puts them together.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdio>
#include <functional>
#include <map>
#include <ostream>
#include <string>
#include <vector>

#include "raykit/ray.hpp"
#include "raykit/sphere.hpp"

#include "box.hpp"
#include "embree.hpp"
#include "exact.hpp"
#include "families.hpp"
#include "kit.hpp"
#include "options.hpp"
#include "peak.hpp"
#include "timing.hpp"
#include "vec.hpp"
#include "vector.hpp"

namespace raykit::bench {


// ---- the data each family carries ------------------------------------------------

struct KitSample {
    raykit::Ray ray;
    raykit::Sphere sphere;
};

struct SphereData {
    SphereFamily family;
    std::vector<ExactSphere> exact;
    std::vector<Sample<double>> wide;    // the same samples, widened to double
    std::vector<KitSample> kit;          // the same samples as the kit's types
    simd::Rays lanes;                    // the same samples as a structure of arrays
    const embree::Scene* embree = nullptr;
};

struct BoxData {
    std::string id, label, description;
    bool whole_box = true;               // false: one rectangle only
    std::vector<Rect3> table;
    std::vector<Vec3<float>> o, d;
    std::vector<raykit::Ray> rays;
    simd::BoxRays lanes;                 // o and d as a structure of arrays
    std::vector<ExactBoxHit> exact;
    const embree::Scene* embree = nullptr;
    const kit::RectTable* kit_table = nullptr;
};

/// The timed batch: the first kBatch rays of a family. 4096 rays are 160 KiB
/// in float (320 KiB in double), inside this kind of CPU's L2 cache, and too
/// many for the branch predictor to learn the hit/miss pattern by heart.
constexpr std::size_t kBatch = 4096;

inline std::size_t batch_size(std::size_t n) { return std::min(n, kBatch); }

// ---- variants -------------------------------------------------------------------

/// What one variant answered for one ray: roots, a first hit, or a box hit.
struct Answer {
    int count = 0;         // 0 miss; 2 roots; 1 a single first hit
    double t[2] = {0, 0};
    int rect = -1;
};

enum class Kind { roots, first_hit, box };

struct Variant {
    std::string id;            // unique, e.g. "stable_f32"
    std::string formulation;   // e.g. "stable"
    std::string label;         // e.g. "stable, float"
    std::string precision;     // "float", "double", "float, double inside"
    std::string group;         // "sphere" or "box"
    int bits = 24;             // significand bits of the result type
    int lanes = 1;             // rays per vector operation (1: scalar, one call per ray)
    std::string isa;           // the vector instruction set (Highway's name), or "" for scalar
    int conversions = 0;       // float <-> double vector conversions per ray (double lanes on float rays)
    Kind kind = Kind::roots;
    std::string note;
    std::string status = "ok";  // ok, absent, not_started, threw: ...
    std::function<Answer(std::size_t family, std::size_t i)> answer;
    std::function<void(std::size_t family)> pass;          // one timed pass over the batch
    std::function<OpCount(std::size_t family, std::size_t i)> count;  // flops of one ray; empty: unknown
    std::function<bool(std::size_t family)> applies = [](std::size_t) { return true; };
};

/// Every sphere variant on `data` (only the kit's own function and an anchor
/// with `subject_only`), and every box variant on `data`.
std::vector<Variant> sphere_variants(const std::vector<SphereData>& data, bool subject_only);
std::vector<Variant> box_variants(const std::vector<BoxData>& data);
/// The vector variants for every instruction set in `targets`.
std::vector<Variant> vector_variants(const std::vector<SphereData>& spheres, const std::vector<BoxData>& boxes,
                                     const std::vector<simd::Target>& targets);

// ---- the error pass ----------------------------------------------------------------

struct ErrorStats {
    std::size_t rays = 0;          // in the family
    std::size_t in_band = 0;       // near a tangent or an edge: not judged
    std::size_t compared = 0;      // judged and both hit: errors measured
    std::size_t misclassified = 0; // judged and the variant disagrees on hit/miss (or on the rectangle)
    double median = 0, p99 = 0, max = 0;  // ulps over `compared`
    // Box families: disagreement with Embree's hit distance, in float ulps.
    std::size_t vs_embree_compared = 0;
    double vs_embree_median = 0, vs_embree_p99 = 0, vs_embree_max = 0;
};

/// The error statistics of variant `v` on family `f`.
ErrorStats sphere_errors(const Variant& v, std::size_t f, const SphereData& data);
/// Also measures the disagreement with `embree` (may be null) on the hit distance.
ErrorStats box_errors(const Variant& v, std::size_t f, const BoxData& data, const Variant* embree);

// ---- output ----------------------------------------------------------------------------

struct Row {
    const Variant* variant;
    std::string family;
    ErrorStats error;
    double flops = -1, div = 0, sqrt = 0, fma = 0;  // per ray, averaged over the timed batch; -1: unknown
};

/// Everything as one JSON document (read by tools/kitlib/bench_report.py).
void write_json(std::ostream& os, const Options& opt, const Peak& peak, const std::vector<simd::Target>& targets,
                const std::vector<SphereData>& spheres,
                const std::vector<BoxData>& boxes, const std::vector<Variant>& variants,
                const std::vector<Row>& rows, const std::map<std::string, Timing>& timings);

}  // namespace raykit::bench
