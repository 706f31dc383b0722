// raykit_bench: speed against error for ray-sphere formulations and the
// Cornell box. ./kit bench runs it and turns its JSON into a table and a plot;
// run it by hand with --help.
//
// Two passes over the same fixed-seed rays:
//   1. error: every variant's answer against the float128 one (exact.hpp), in
//      ulps of the variant's result type, plus hit/miss misclassifications
//      outside a near-tangent (or near-edge) band;
//   2. speed: Google Benchmark times one pass over a batch of rays (small
//      enough to stay in cache), several repetitions interleaved at random so
//      a noisy neighbour hurts every variant alike.
// Every variant is called out of line, one call per ray, as the kit's step
// functions are; results go to an array the compiler must write.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#if defined(__SSE2__)
#include <pmmintrin.h>
#include <xmmintrin.h>
#endif

#include "raykit/not_implemented.hpp"

#include "box.hpp"
#include "embree.hpp"
#include "exact.hpp"
#include "families.hpp"
#include "formulations.hpp"
#include "kit.hpp"
#include "peak.hpp"
#include "vec.hpp"

namespace rb = raykit::bench;
using rb::Sample;
using rb::Vec3;

namespace {

// ---- options ---------------------------------------------------------------------

struct Options {
    std::size_t rays = 100000;   // per family, for the error pass
    int repetitions = 15;        // timed repetitions per variant and family
    double min_time = 0.01;      // seconds per repetition, about
    double peak_time = 0.05;     // seconds per peak kernel
    bool subject_only = false;   // only the kit's sphere subject (the student build)
    std::string out;             // JSON file; stdout when empty
};

const char* kUsage =
    "usage: raykit_bench [--quick | --smoke] [--rays=N] [--repetitions=N] [--min-time=SECONDS]\n"
    "                    [--subject-only] [--out=FILE]\n"
    "\n"
    "Measures the error (against float128) and the speed of ray-sphere formulations,\n"
    "the kit's own step functions and Embree, and writes the results as JSON.\n"
    "  --quick           fewer rays and repetitions (a few seconds)\n"
    "  --smoke           a tiny run that only checks everything works\n"
    "  --rays=N          rays per family for the error pass (default 100000)\n"
    "  --repetitions=N   timed repetitions per variant and family (default 15)\n"
    "  --min-time=S      seconds each repetition runs, about (default 0.01)\n"
    "  --subject-only    only the kit's sphere function of this build (for a student build)\n"
    "  --out=FILE        write the JSON here (written to FILE.tmp, then renamed)\n";

[[noreturn]] void usage_error(const std::string& message) {
    std::fprintf(stderr, "raykit_bench: %s\n%s", message.c_str(), kUsage);
    std::exit(2);
}

long parse_count(const std::string& name, const std::string& text, long lo, long hi) {
    char* end = nullptr;
    errno = 0;
    const long v = std::strtol(text.c_str(), &end, 10);
    if (text.empty() || *end != '\0' || errno != 0 || v < lo || v > hi) {
        usage_error(name + " wants a whole number from " + std::to_string(lo) + " to " + std::to_string(hi) +
                    ", not '" + text + "'");
    }
    return v;
}

double parse_seconds(const std::string& name, const std::string& text) {
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !std::isfinite(v) || v <= 0 || v > 10) {
        usage_error(name + " wants seconds, more than 0 and at most 10, not '" + text + "'");
    }
    return v;
}

Options parse(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        const auto eq = arg.find('=');
        const std::string key = arg.substr(0, eq);
        const std::string value = eq == std::string::npos ? "" : arg.substr(eq + 1);
        const bool has_value = eq != std::string::npos;
        auto need_value = [&] { if (!has_value) usage_error(key + " needs a value: " + key + "=..."); };
        auto no_value = [&] { if (has_value) usage_error(key + " takes no value"); };
        if (key == "--help" || key == "-h") {
            std::fputs(kUsage, stdout);
            std::exit(0);
        } else if (key == "--quick") {
            no_value();
            o.rays = 10000, o.repetitions = 5, o.min_time = 0.004, o.peak_time = 0.01;
        } else if (key == "--smoke") {
            no_value();
            o.rays = 300, o.repetitions = 1, o.min_time = 1e-4, o.peak_time = 1e-3;
        } else if (key == "--rays") {
            need_value();
            o.rays = static_cast<std::size_t>(parse_count(key, value, 10, 10000000));
        } else if (key == "--repetitions") {
            need_value();
            o.repetitions = static_cast<int>(parse_count(key, value, 1, 100));
        } else if (key == "--min-time") {
            need_value();
            o.min_time = parse_seconds(key, value);
        } else if (key == "--subject-only") {
            no_value();
            o.subject_only = true;
        } else if (key == "--out") {
            need_value();
            if (value.empty()) usage_error("--out needs a file name");
            o.out = value;
        } else {
            usage_error("unknown option '" + arg + "'");
        }
    }
    return o;
}

void progress(const char* phase, std::size_t done, std::size_t total, const std::string& what) {
    // One line per step; ./kit bench turns these into its progress display.
    std::fprintf(stderr, "progress %s %zu %zu %s\n", phase, done, total, what.c_str());
    std::fflush(stderr);
}

// ---- the data each family carries ----------------------------------------------------

struct KitSample {
    raykit::Ray ray;
    raykit::Sphere sphere;
};

struct SphereData {
    rb::SphereFamily family;
    std::vector<rb::ExactSphere> exact;
    std::vector<Sample<double>> wide;    // the same samples, widened to double
    std::vector<KitSample> kit;          // the same samples as the kit's types
    const rb::embree::Scene* embree = nullptr;
};

struct BoxData {
    std::string id, label, description;
    bool whole_box = true;               // false: one rectangle only
    std::vector<rb::Rect3> table;
    std::vector<Vec3<float>> o, d;
    std::vector<raykit::Ray> rays;
    std::vector<rb::ExactBoxHit> exact;
    const rb::embree::Scene* embree = nullptr;
    const rb::kit::RectTable* kit_table = nullptr;
};

/// The timed batch: the first kBatch rays of a family. 4096 rays are 160 KiB
/// in float (320 KiB in double), inside this kind of CPU's L2 cache, and too
/// many for the branch predictor to learn the hit/miss pattern by heart.
constexpr std::size_t kBatch = 4096;

std::size_t batch_size(std::size_t n) { return std::min(n, kBatch); }

// Where timed results go; one of each, reused.
std::vector<rb::RootsOf<float>> g_out_f(kBatch);
std::vector<rb::RootsOf<double>> g_out_d(kBatch);
std::vector<raykit::Roots> g_out_kit(kBatch);
std::vector<rb::BoxHit> g_out_box(kBatch);

// ---- variants ------------------------------------------------------------------------

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
    Kind kind = Kind::roots;
    std::string note;
    std::string status = "ok";  // ok, absent, not_started, threw: ...
    std::function<Answer(std::size_t family, std::size_t i)> answer;
    std::function<void(std::size_t family)> pass;          // one timed pass over the batch
    std::function<rb::OpCount(std::size_t family, std::size_t i)> count;  // flops of one ray; empty: unknown
    std::function<bool(std::size_t family)> applies = [](std::size_t) { return true; };
};

template <class In, class Out, Out (*F)(const In&)>
__attribute__((noinline)) Out out_of_line(const In& in) {
    return F(in);
}

template <class T>
Answer from_roots(const rb::RootsOf<T>& r) {
    Answer a;
    a.count = r.count;
    a.t[0] = static_cast<double>(r.t[0]);
    a.t[1] = static_cast<double>(r.t[1]);
    return a;
}

Answer from_box(const rb::BoxHit& h) {
    Answer a;
    if (h.hit) {
        a.count = 1;
        a.t[0] = h.t;
        a.rect = h.rect;
    }
    return a;
}

template <class T, rb::RootsOf<T> (*F)(const Sample<T>&), rb::RootsOf<rb::Counted<float>> (*C)(
                                                            const Sample<rb::Counted<float>>&)>
Variant formulation(const std::vector<SphereData>& data, const char* name, const char* precision_word) {
    constexpr bool wide = std::is_same_v<T, double>;
    Variant v;
    v.formulation = name;
    v.precision = wide ? "double" : "float";
    v.id = std::string(name) + (wide ? "_f64" : "_f32");
    v.label = std::string(name) + ", " + precision_word;
    v.group = "sphere";
    v.bits = wide ? 53 : 24;
    const auto* d = &data;
    v.answer = [d](std::size_t f, std::size_t i) {
        if constexpr (wide) return from_roots(out_of_line<Sample<T>, rb::RootsOf<T>, F>((*d)[f].wide[i]));
        else return from_roots(out_of_line<Sample<T>, rb::RootsOf<T>, F>((*d)[f].family.samples[i]));
    };
    v.pass = [d](std::size_t f) {
        const auto& fam = (*d)[f];
        const std::size_t n = batch_size(fam.family.samples.size());
        if constexpr (wide) {
            const Sample<double>* in = fam.wide.data();
            for (std::size_t i = 0; i < n; ++i) g_out_d[i] = out_of_line<Sample<T>, rb::RootsOf<T>, F>(in[i]);
        } else {
            const Sample<float>* in = fam.family.samples.data();
            for (std::size_t i = 0; i < n; ++i) g_out_f[i] = out_of_line<Sample<T>, rb::RootsOf<T>, F>(in[i]);
        }
    };
    v.count = [d](std::size_t f, std::size_t i) {
        rb::op_count() = {};
        C(rb::convert<rb::Counted<float>>((*d)[f].family.samples[i]));
        return rb::op_count();
    };
    return v;
}

std::vector<Variant> sphere_variants(const std::vector<SphereData>& data, bool subject_only) {
    using rb::Counted;
    std::vector<Variant> out;
    if (subject_only) {
        // An anchor timed in both runs, so ./kit bench can put the student's
        // times, measured in another process, on the reference run's scale.
        out.push_back(formulation<float, rb::stable<float>, rb::stable<Counted<float>>>(data, "stable", "float"));
    } else {
        out.push_back(formulation<float, rb::textbook<float>, rb::textbook<Counted<float>>>(data, "textbook", "float"));
        out.push_back(formulation<double, rb::textbook<double>, rb::textbook<Counted<float>>>(data, "textbook", "double"));
        out.push_back(formulation<float, rb::half_b<float>, rb::half_b<Counted<float>>>(data, "half-b", "float"));
        out.push_back(formulation<double, rb::half_b<double>, rb::half_b<Counted<float>>>(data, "half-b", "double"));
        out.push_back(formulation<float, rb::unit_dir<float>, rb::unit_dir<Counted<float>>>(data, "unit-dir", "float"));
        out.push_back(formulation<double, rb::unit_dir<double>, rb::unit_dir<Counted<float>>>(data, "unit-dir", "double"));
        out.push_back(formulation<float, rb::geometric<float>, rb::geometric<Counted<float>>>(data, "geometric", "float"));
        out.push_back(formulation<double, rb::geometric<double>, rb::geometric<Counted<float>>>(data, "geometric", "double"));
        out.push_back(formulation<float, rb::stable<float>, rb::stable<Counted<float>>>(data, "stable", "float"));
        out.push_back(formulation<double, rb::stable<double>, rb::stable<Counted<float>>>(data, "stable", "double"));
        for (Variant mixed : {formulation<float, rb::in_double<rb::half_b<double>>, rb::half_b<Counted<float>>>(
                                  data, "half-b", ""),
                              formulation<float, rb::in_double<rb::stable<double>>, rb::stable<Counted<float>>>(
                                  data, "stable", "")}) {
            mixed.id = mixed.formulation + "_f32_in_f64";
            mixed.label = mixed.formulation + ", double inside";
            mixed.precision = "float, double inside";
            out.push_back(mixed);
        }
    }

    // The kit's own function: step 02's sphere_roots, or step 01 after a move.
    Variant kit;
    kit.id = "kit";
    kit.formulation = "kit";
    kit.group = "sphere";
    kit.precision = "float";
    const int step = rb::kit::sphere_step();
    kit.label = step == 2 ? "kit step 02" : "kit step 01, ray moved to the unit sphere";
    kit.note = step == 2   ? "sphere_roots(ray, sphere) of step 02"
               : step == 1 ? "step 02 is not in this kit yet: step 01's unit_sphere_roots after o' = (o - c)/r, "
                             "d' = d/r"
                           : "no sphere step is built";
    if (step == 0) kit.status = "absent";
    const auto* d = &data;
    kit.answer = [d](std::size_t f, std::size_t i) {
        const KitSample& s = (*d)[f].kit[i];
        const raykit::Roots r = rb::kit::sphere_roots(s.ray, s.sphere);
        Answer a;
        a.count = r.count == 0 ? 0 : 2;  // a tangent (count 1) repeats its root in t[1]
        a.t[0] = r.t[0];
        a.t[1] = r.t[1];
        return a;
    };
    kit.pass = [d](std::size_t f) {
        const auto& fam = (*d)[f];
        const std::size_t n = batch_size(fam.kit.size());
        const KitSample* in = fam.kit.data();
        for (std::size_t i = 0; i < n; ++i) g_out_kit[i] = rb::kit::sphere_roots(in[i].ray, in[i].sphere);
    };
    out.push_back(kit);

    if (!subject_only) {
        Variant e;
        e.id = "embree_sphere";
        e.formulation = "embree";
        e.label = "Embree sphere point";
        e.precision = "float";
        e.group = "sphere";
        e.kind = Kind::first_hit;
        e.note = "rtcIntersect1 on one RTC_GEOMETRY_TYPE_SPHERE_POINT; only the first hit in [0, inf) is "
                 "returned, so its error is that hit's";
        if (!rb::embree::available()) e.status = "absent";
        e.answer = [d](std::size_t f, std::size_t i) {
            const Sample<float>& s = (*d)[f].family.samples[i];
            return from_box(rb::embree::intersect((*d)[f].embree, s.o, s.d, 0.0f));
        };
        e.pass = [d](std::size_t f) {
            const auto& fam = (*d)[f];
            const std::size_t n = batch_size(fam.family.samples.size());
            const Sample<float>* in = fam.family.samples.data();
            for (std::size_t i = 0; i < n; ++i) g_out_box[i] = rb::embree::intersect(fam.embree, in[i].o, in[i].d, 0.0f);
        };
        out.push_back(e);
    }
    return out;
}

rb::BoxHit own_brute_force(const BoxData& b, std::size_t i) {
    return rb::brute_force<float>(b.o[i], b.d[i], b.table.data(), static_cast<int>(b.table.size()), 0.0f);
}

__attribute__((noinline)) rb::BoxHit own_brute_force_call(const Vec3<float>& o, const Vec3<float>& d,
                                                          const rb::Rect3* rects, int n) {
    return rb::brute_force<float>(o, d, rects, n, 0.0f);
}

std::vector<Variant> box_variants(const std::vector<BoxData>& data) {
    std::vector<Variant> out;
    const auto* d = &data;
    auto base = [](const char* id, const char* formulation, const char* label) {
        Variant v;
        v.id = id;
        v.formulation = formulation;
        v.label = label;
        v.precision = "float";
        v.group = "box";
        v.kind = Kind::box;
        return v;
    };

    Variant own = base("brute_force", "brute force", "brute force, the benchmark's loop");
    own.note = "hit_rect over the table in bench/box.hpp, closest hit shrinks the window";
    own.answer = [d](std::size_t f, std::size_t i) { return from_box(own_brute_force((*d)[f], i)); };
    own.pass = [d](std::size_t f) {
        const BoxData& b = (*d)[f];
        const std::size_t n = batch_size(b.o.size());
        const int rects = static_cast<int>(b.table.size());
        for (std::size_t i = 0; i < n; ++i) g_out_box[i] = own_brute_force_call(b.o[i], b.d[i], b.table.data(), rects);
    };
    own.count = [d](std::size_t f, std::size_t i) {
        const BoxData& b = (*d)[f];
        rb::op_count() = {};
        const auto wide = [](const Vec3<float>& v) {
            return Vec3<rb::Counted<float>>{v.x, v.y, v.z};
        };
        rb::brute_force<rb::Counted<float>>(wide(b.o[i]), wide(b.d[i]), b.table.data(),
                                             static_cast<int>(b.table.size()), 0.0f);
        return rb::op_count();
    };
    out.push_back(own);

    Variant kit = base("kit_rect", "kit", "kit step 04, intersect_rect over the table");
    kit.note = "raykit::intersect_rect for each rectangle, window shrinking";
    if (!rb::kit::has_rect()) kit.status = "absent";
    kit.answer = [d](std::size_t f, std::size_t i) {
        return from_box(rb::kit::brute_force((*d)[f].kit_table, (*d)[f].rays[i], 0.0f));
    };
    kit.pass = [d](std::size_t f) {
        const BoxData& b = (*d)[f];
        const std::size_t n = batch_size(b.rays.size());
        for (std::size_t i = 0; i < n; ++i) g_out_box[i] = rb::kit::brute_force(b.kit_table, b.rays[i], 0.0f);
    };
    out.push_back(kit);

    Variant scene = base("kit_scene", "kit", "kit step 05, find_intersection");
    scene.note = "raykit::find_intersection over raykit::cornell_box()";
    if (!rb::kit::has_scene()) scene.status = "absent";
    scene.applies = [d](std::size_t f) { return (*d)[f].whole_box; };
    scene.answer = [d](std::size_t f, std::size_t i) { return from_box(rb::kit::find_intersection((*d)[f].rays[i], 0.0f)); };
    scene.pass = [d](std::size_t f) {
        const BoxData& b = (*d)[f];
        const std::size_t n = batch_size(b.rays.size());
        for (std::size_t i = 0; i < n; ++i) g_out_box[i] = rb::kit::find_intersection(b.rays[i], 0.0f);
    };
    out.push_back(scene);

    Variant e = base("embree_quads", "embree", "Embree quads");
    e.note = "rtcIntersect1 on one RTC_GEOMETRY_TYPE_QUAD geometry, one quad per rectangle";
    if (!rb::embree::available()) e.status = "absent";
    e.answer = [d](std::size_t f, std::size_t i) {
        return from_box(rb::embree::intersect((*d)[f].embree, (*d)[f].o[i], (*d)[f].d[i], 0.0f));
    };
    e.pass = [d](std::size_t f) {
        const BoxData& b = (*d)[f];
        const std::size_t n = batch_size(b.o.size());
        for (std::size_t i = 0; i < n; ++i) g_out_box[i] = rb::embree::intersect(b.embree, b.o[i], b.d[i], 0.0f);
    };
    out.push_back(e);
    return out;
}

// ---- the error pass ---------------------------------------------------------------

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

/// Nearest-rank percentile of sorted values.
double percentile(const std::vector<double>& sorted, double p) {
    if (sorted.empty()) return 0;
    const auto rank = static_cast<std::size_t>(std::ceil(p * static_cast<double>(sorted.size())));
    return sorted[std::min(sorted.size() - 1, rank == 0 ? 0 : rank - 1)];
}

void summarise(std::vector<double>& errors, double& median, double& p99, double& max) {
    std::sort(errors.begin(), errors.end());
    median = percentile(errors, 0.5);
    p99 = percentile(errors, 0.99);
    max = errors.empty() ? 0 : errors.back();
}

ErrorStats sphere_errors(const Variant& v, std::size_t f, const SphereData& data) {
    ErrorStats s;
    std::vector<double> errors;
    const std::size_t n = data.family.samples.size();
    s.rays = n;
    for (std::size_t i = 0; i < n; ++i) {
        const rb::ExactSphere& e = data.exact[i];
        if (e.near_tangent) {
            ++s.in_band;
            continue;
        }
        const Answer a = v.answer(f, i);
        if (v.kind == Kind::first_hit) {
            rb::quad t;
            const bool hit = rb::first_hit(e, t);
            if (hit != (a.count > 0)) {
                ++s.misclassified;
            } else if (hit) {
                ++s.compared;
                errors.push_back(rb::ulps(t, a.t[0], v.bits));
            }
            continue;
        }
        if (e.hit != (a.count > 0)) {
            ++s.misclassified;
        } else if (e.hit) {
            ++s.compared;
            errors.push_back(std::max(rb::ulps(e.t[0], a.t[0], v.bits), rb::ulps(e.t[1], a.t[1], v.bits)));
        }
    }
    summarise(errors, s.median, s.p99, s.max);
    return s;
}

ErrorStats box_errors(const Variant& v, std::size_t f, const BoxData& data, const Variant* embree) {
    ErrorStats s;
    std::vector<double> errors, vs;
    const std::size_t n = data.o.size();
    s.rays = n;
    for (std::size_t i = 0; i < n; ++i) {
        const rb::ExactBoxHit& e = data.exact[i];
        if (e.near_edge) {
            ++s.in_band;
            continue;
        }
        const Answer a = v.answer(f, i);
        const bool hit = a.count > 0;
        const bool other_rect = hit && a.rect >= 0 && a.rect != e.rect && a.rect != e.tie;
        if (hit != e.hit || other_rect) {
            ++s.misclassified;
            continue;
        }
        if (!hit) continue;
        ++s.compared;
        errors.push_back(rb::ulps(e.t, a.t[0], 24));
        if (embree && embree != &v) {
            const Answer b = embree->answer(f, i);
            if (b.count > 0 && (b.rect == a.rect || (e.tie >= 0 && (b.rect == e.tie || b.rect == e.rect)))) {
                ++s.vs_embree_compared;
                vs.push_back(rb::ulps(rb::quad(b.t[0]), a.t[0], 24));  // in ulps at Embree's value
            }
        }
    }
    summarise(errors, s.median, s.p99, s.max);
    summarise(vs, s.vs_embree_median, s.vs_embree_p99, s.vs_embree_max);
    return s;
}

// ---- timing ---------------------------------------------------------------------------

/// Per repetition: nanoseconds per ray, CPU time (the process's own time, so a
/// neighbour that takes the core away does not count) and wall-clock time.
struct Timing {
    std::vector<double> cpu_ns, real_ns;
};

/// Google Benchmark calls this after each run; it keeps the per-repetition
/// times and prints progress instead of the usual console table.
class Collector : public benchmark::BenchmarkReporter {
public:
    Collector(std::map<std::string, Timing>& into, std::map<std::string, std::size_t>& rays_per_iteration,
              std::size_t total)
        : into_(into), rays_(rays_per_iteration), total_(total) {}

    bool ReportContext(const Context&) override { return true; }

    void ReportRuns(const std::vector<Run>& runs) override {
        for (const Run& run : runs) {
            if (run.run_type != Run::RT_Iteration) continue;
            const std::string& name = run.run_name.function_name;
            if (run.error_occurred) {
                std::fprintf(stderr, "raykit_bench: %s: %s\n", name.c_str(), run.error_message.c_str());
                continue;
            }
            const double rays = static_cast<double>(rays_.at(name));
            into_[name].cpu_ns.push_back(run.GetAdjustedCPUTime() / rays);
            into_[name].real_ns.push_back(run.GetAdjustedRealTime() / rays);
            ++done_;
            if (done_ == total_ || done_ % 8 == 0) progress("speed", done_, total_, name);
        }
    }

private:
    std::map<std::string, Timing>& into_;
    std::map<std::string, std::size_t>& rays_;
    std::size_t total_;
    std::size_t done_ = 0;
};

struct Job {
    std::string name;   // variant/family
    std::function<void()> pass;
    std::size_t rays;
};

/// How many passes over the batch fill `seconds`: the fastest of three
/// passes, timed with the steady clock (which also warms the caches).
benchmark::IterationCount calibrate(const std::function<void()>& pass, double seconds) {
    double best = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 3; ++i) {
        const auto t0 = std::chrono::steady_clock::now();
        pass();
        best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    return static_cast<benchmark::IterationCount>(std::max(1.0, std::ceil(seconds / std::max(best, 1e-9))));
}

std::map<std::string, Timing> time_jobs(const std::vector<Job>& jobs, const Options& opt, const char* argv0) {
    std::map<std::string, Timing> timings;
    std::map<std::string, std::size_t> rays;
    for (const Job& job : jobs) {
        rays[job.name] = job.rays;
        const auto pass = job.pass;
        // A fixed iteration count: Google Benchmark would otherwise search for
        // one before every interleaved repetition, which costs more than the
        // measurement itself.
        benchmark::RegisterBenchmark(job.name.c_str(),
                                     [pass](benchmark::State& state) {
                                         for (auto _ : state) {
                                             pass();
                                             benchmark::ClobberMemory();
                                         }
                                     })
            ->Repetitions(opt.repetitions)
            ->Iterations(calibrate(pass, opt.min_time))
            ->Unit(benchmark::kNanosecond);
    }
    // Interleave the repetitions of all benchmarks at random: slow spells of
    // a shared machine then spread over every variant instead of hitting one.
    std::string program = argv0;
    std::string interleave = "--benchmark_enable_random_interleaving=true";
    char* args[] = {program.data(), interleave.data(), nullptr};
    int count = 2;
    benchmark::Initialize(&count, args);
    Collector collector(timings, rays, jobs.size() * static_cast<std::size_t>(opt.repetitions));
    benchmark::RunSpecifiedBenchmarks(&collector);
    benchmark::Shutdown();
    return timings;
}

// ---- output ---------------------------------------------------------------------------

std::string quote(const std::string& text) {
    std::string q = "\"";
    for (const char c : text) {
        if (c == '"' || c == '\\') {
            q += '\\';
            q += c;
        } else if (static_cast<unsigned char>(c) < 0x20) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\u%04x", c);
            q += buf;
        } else {
            q += c;
        }
    }
    return q + "\"";
}

std::string number(double x) {
    if (!std::isfinite(x)) return "null";  // JSON has no infinity; the reader reads null as "infinite"
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.9g", x);
    return buf;
}

std::string numbers(const std::vector<double>& xs) {
    std::string s = "[";
    for (std::size_t i = 0; i < xs.size(); ++i) s += (i ? ", " : "") + number(xs[i]);
    return s + "]";
}

struct Row {
    const Variant* variant;
    std::string family;
    ErrorStats error;
    double flops = -1, div = 0, sqrt = 0;  // per ray, averaged over the timed batch; -1: unknown
};

std::string cpu_model() {
    std::ifstream in("/proc/cpuinfo");
    std::string line;
    while (std::getline(in, line)) {
        if (line.rfind("model name", 0) == 0) {
            const auto colon = line.find(':');
            if (colon != std::string::npos) return line.substr(colon + 2);
        }
    }
    return "unknown";
}

std::string build_flags() {
#ifdef RAYKIT_BENCH_FLAGS
    return RAYKIT_BENCH_FLAGS;
#else
    return "";
#endif
}

void write_json(std::ostream& os, const Options& opt, const rb::Peak& peak, const std::vector<SphereData>& spheres,
                const std::vector<BoxData>& boxes, const std::vector<Variant>& variants, const std::vector<Row>& rows,
                const std::map<std::string, Timing>& timings) {
    const auto& cpu = benchmark::CPUInfo::Get();
    os << "{\n  \"meta\": {";
    os << "\"cpu\": " << quote(cpu_model()) << ", \"cpus\": " << cpu.num_cpus
       << ", \"mhz\": " << number(cpu.cycles_per_second / 1e6) << ", \"load_avg\": " << numbers(cpu.load_avg)
       << ", \"compiler\": " << quote(__VERSION__) << ", \"flags\": " << quote(build_flags())
       << ", \"rays\": " << opt.rays << ", \"batch\": " << batch_size(opt.rays)
       << ", \"repetitions\": " << opt.repetitions << ", \"min_time\": " << number(opt.min_time)
       << ", \"tangent_band\": " << number(rb::kTangentBand) << ", \"edge_band\": " << number(rb::kEdgeBand)
       << ", \"embree\": " << quote(rb::embree::status()) << ", \"sphere_step\": " << rb::kit::sphere_step()
       << ", \"rect_step\": " << (rb::kit::has_rect() ? "true" : "false")
       << ", \"scene_step\": " << (rb::kit::has_scene() ? "true" : "false") << "},\n";
    os << "  \"peak\": {\"scalar_gflops_f32\": " << number(peak.scalar_gflops_f32)
       << ", \"scalar_gflops_f64\": " << number(peak.scalar_gflops_f64)
       << ", \"vector_gflops_f32\": " << number(peak.vector_gflops_f32)
       << ", \"vector_gflops_f64\": " << number(peak.vector_gflops_f64) << ", \"vector_isa\": " << quote(peak.vector_isa)
       << ", \"div_ns_f32\": " << number(peak.div_ns_f32) << ", \"sqrt_ns_f32\": " << number(peak.sqrt_ns_f32)
       << ", \"div_ns_f64\": " << number(peak.div_ns_f64) << ", \"sqrt_ns_f64\": " << number(peak.sqrt_ns_f64)
       << "},\n";
    os << "  \"families\": [\n";
    bool first = true;
    for (const auto& s : spheres) {
        os << (first ? "" : ",\n") << "    {\"id\": " << quote(s.family.id) << ", \"label\": " << quote(s.family.label)
           << ", \"group\": \"sphere\", \"hard\": " << (s.family.hard ? "true" : "false")
           << ", \"description\": " << quote(s.family.description) << "}";
        first = false;
    }
    for (const auto& b : boxes) {
        os << (first ? "" : ",\n") << "    {\"id\": " << quote(b.id) << ", \"label\": " << quote(b.label)
           << ", \"group\": \"box\", \"hard\": false, \"description\": " << quote(b.description) << "}";
        first = false;
    }
    os << "\n  ],\n  \"variants\": [\n";
    for (std::size_t i = 0; i < variants.size(); ++i) {
        const Variant& v = variants[i];
        os << (i ? ",\n" : "") << "    {\"id\": " << quote(v.id) << ", \"formulation\": " << quote(v.formulation)
           << ", \"label\": " << quote(v.label) << ", \"precision\": " << quote(v.precision)
           << ", \"group\": " << quote(v.group) << ", \"ulp_of\": " << (v.bits == 24 ? "\"float\"" : "\"double\"")
           << ", \"status\": " << quote(v.status) << ", \"note\": " << quote(v.note) << "}";
    }
    os << "\n  ],\n  \"results\": [\n";
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const Row& r = rows[i];
        const ErrorStats& e = r.error;
        const std::string name = r.variant->id + "/" + r.family;
        const auto t = timings.find(name);
        os << (i ? ",\n" : "") << "    {\"variant\": " << quote(r.variant->id) << ", \"family\": " << quote(r.family)
           << ", \"rays\": " << e.rays << ", \"in_band\": " << e.in_band << ", \"compared\": " << e.compared
           << ", \"misclassified\": " << e.misclassified << ", \"ulps_median\": " << number(e.median)
           << ", \"ulps_p99\": " << number(e.p99) << ", \"ulps_max\": " << number(e.max);
        if (r.variant->group == "box") {
            os << ", \"vs_embree_compared\": " << e.vs_embree_compared
               << ", \"vs_embree_median\": " << number(e.vs_embree_median)
               << ", \"vs_embree_p99\": " << number(e.vs_embree_p99) << ", \"vs_embree_max\": " << number(e.vs_embree_max);
        }
        os << ", \"flops\": " << (r.flops < 0 ? "null" : number(r.flops)) << ", \"div\": " << number(r.div)
           << ", \"sqrt\": " << number(r.sqrt);
        if (t != timings.end()) {
            os << ", \"cpu_ns\": " << numbers(t->second.cpu_ns) << ", \"real_ns\": " << numbers(t->second.real_ns);
        } else {
            os << ", \"cpu_ns\": [], \"real_ns\": []";
        }
        os << "}";
    }
    os << "\n  ]\n}\n";
}

// ---- setting up the families --------------------------------------------------------

std::vector<SphereData> make_spheres(std::size_t n, bool with_embree) {
    std::vector<SphereData> out;
    for (rb::SphereFamily& f : rb::sphere_families(n)) {
        SphereData d;
        d.family = std::move(f);
        for (const Sample<float>& s : d.family.samples) {
            d.exact.push_back(rb::exact_sphere(s));
            d.wide.push_back(rb::convert<double>(s));
            d.kit.push_back({{{s.o.x, s.o.y, s.o.z}, {s.d.x, s.d.y, s.d.z}}, {{s.c.x, s.c.y, s.c.z}, s.r}});
        }
        if (with_embree) d.embree = rb::embree::sphere(d.family.samples[0].c, d.family.samples[0].r);
        progress("setup", out.size() + 1, 9, d.family.id);
        out.push_back(std::move(d));
    }
    return out;
}

std::vector<BoxData> make_boxes(std::size_t n, std::string& note) {
    std::vector<rb::Rect3> box;
    try {
        box = rb::kit::box_table();
    } catch (const std::exception& e) {
        note = std::string("cornell_box() failed (") + e.what() + "); the benchmark's own table is used";
        box.assign(rb::kCornellBox, rb::kCornellBox + rb::kBoxRects);
    }
    // The back wall: the rectangle at z = 555, or else the last one.
    std::vector<rb::Rect3> back_wall = {box.back()};
    for (const rb::Rect3& r : box) {
        if (r.axis == 2 && r.offset > 500) back_wall = {r};
    }
    std::vector<BoxData> out;
    for (rb::BoxFamily& f : rb::box_families(n)) {
        BoxData b;
        b.id = f.id;
        b.label = f.label;
        b.description = f.description;
        b.table = box;
        b.o = std::move(f.origins);
        b.d = std::move(f.directions);
        out.push_back(std::move(b));
        if (out.back().id == "box_camera") {  // the same rays against the back wall alone
            BoxData one = out.back();
            one.id = "rect_camera";
            one.label = "one rectangle, camera rays";
            one.description = "the camera rays against the back wall alone";
            one.whole_box = false;
            one.table = back_wall;
            out.push_back(std::move(one));
        }
    }
    for (BoxData& b : out) {
        for (std::size_t i = 0; i < b.o.size(); ++i) {
            b.rays.push_back({{b.o[i].x, b.o[i].y, b.o[i].z}, {b.d[i].x, b.d[i].y, b.d[i].z}});
            b.exact.push_back(rb::exact_box(b.o[i], b.d[i], b.table.data(), static_cast<int>(b.table.size()), 0.0f));
        }
        if (rb::embree::available()) b.embree = rb::embree::quads(b.table);
        if (rb::kit::has_rect()) b.kit_table = rb::kit::rect_table(b.table);
    }
    return out;
}

/// Average operation counts over the timed batch, or -1 flops when unknown.
void count_ops(const Variant& v, std::size_t f, std::size_t n, Row& row) {
    if (!v.count) return;
    double flops = 0, div = 0, sqrt = 0;
    const std::size_t m = batch_size(n);
    for (std::size_t i = 0; i < m; ++i) {
        const rb::OpCount c = v.count(f, i);
        flops += static_cast<double>(c.flops());
        div += static_cast<double>(c.div);
        sqrt += static_cast<double>(c.sqrt);
    }
    row.flops = flops / static_cast<double>(m);
    row.div = div / static_cast<double>(m);
    row.sqrt = sqrt / static_cast<double>(m);
}

/// Runs the error pass of the kit's subject once, to learn whether it is
/// written: a stub throws raykit::not_implemented.
void probe_subject(Variant& kit, const std::vector<SphereData>& spheres) {
    if (kit.status != "ok") return;
    try {
        for (std::size_t f = 0; f < spheres.size(); ++f) {
            for (std::size_t i = 0; i < spheres[f].family.samples.size(); ++i) kit.answer(f, i);
        }
    } catch (const raykit::not_implemented&) {
        kit.status = "not_started";
    } catch (const std::exception& e) {
        kit.status = std::string("threw: ") + e.what();
    }
}

int run(const Options& opt, const char* argv0, std::ofstream& file) {
#if defined(__SSE2__)
    // Embree asks for flush-to-zero and denormals-are-zero; no input or result
    // of this benchmark is a denormal, so the other variants are unaffected.
    _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
    _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
#endif
    const bool embree = !opt.subject_only && rb::embree::available();
    std::vector<SphereData> spheres = make_spheres(opt.rays, embree);
    std::string box_note;
    std::vector<BoxData> boxes;
    if (!opt.subject_only) boxes = make_boxes(opt.rays, box_note);

    std::vector<Variant> variants = sphere_variants(spheres, opt.subject_only);
    for (Variant& v : variants) {
        if (v.id == "kit") probe_subject(v, spheres);
    }
    if (!opt.subject_only) {
        for (Variant& v : box_variants(boxes)) variants.push_back(std::move(v));
        if (!box_note.empty()) {
            for (Variant& v : variants) {
                if (v.id == "kit_scene") v.note += "; " + box_note;
            }
        }
    }
    const Variant* embree_quads = nullptr;
    for (const Variant& v : variants) {
        if (v.id == "embree_quads" && v.status == "ok") embree_quads = &v;
    }

    // The error pass.
    std::vector<Row> rows;
    std::vector<Job> jobs;
    const std::size_t families = spheres.size() + boxes.size();
    std::size_t done = 0;
    for (std::size_t f = 0; f < spheres.size(); ++f) {
        for (const Variant& v : variants) {
            if (v.group != "sphere" || v.status != "ok") continue;
            Row row{&v, spheres[f].family.id, sphere_errors(v, f, spheres[f])};
            count_ops(v, f, spheres[f].family.samples.size(), row);
            rows.push_back(row);
            const auto pass = v.pass;
            jobs.push_back({v.id + "/" + row.family, [pass, f] { pass(f); }, batch_size(spheres[f].kit.size())});
        }
        progress("error", ++done, families, spheres[f].family.label);
    }
    for (std::size_t f = 0; f < boxes.size(); ++f) {
        for (const Variant& v : variants) {
            if (v.group != "box" || v.status != "ok" || !v.applies(f)) continue;
            Row row{&v, boxes[f].id, box_errors(v, f, boxes[f], embree_quads)};
            count_ops(v, f, boxes[f].o.size(), row);
            rows.push_back(row);
            const auto pass = v.pass;
            jobs.push_back({v.id + "/" + row.family, [pass, f] { pass(f); }, batch_size(boxes[f].o.size())});
        }
        progress("error", ++done, families, boxes[f].label);
    }

    rb::Peak peak;
    if (!opt.subject_only) {
        progress("peak", 0, 1, "");
        peak = rb::measure_peak(opt.peak_time);
        progress("peak", 1, 1, "");
    }

    const std::map<std::string, Timing> timings = time_jobs(jobs, opt, argv0);

    if (opt.out.empty()) {
        write_json(std::cout, opt, peak, spheres, boxes, variants, rows, timings);
        return std::cout.good() ? 0 : 1;
    }
    write_json(file, opt, peak, spheres, boxes, variants, rows, timings);
    file.close();
    if (!file) {
        std::fprintf(stderr, "raykit_bench: writing %s.tmp failed\n", opt.out.c_str());
        return 1;
    }
    const std::string tmp = opt.out + ".tmp";
    if (std::rename(tmp.c_str(), opt.out.c_str()) != 0) {
        std::fprintf(stderr, "raykit_bench: cannot rename %s to %s\n", tmp.c_str(), opt.out.c_str());
        return 1;
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    const Options opt = parse(argc, argv);
    // The output file is opened first, so a bad --out fails at once rather
    // than after a minute of measuring; it is written as FILE.tmp and renamed
    // at the end, so a failed run never leaves a half-written FILE.
    std::ofstream file;
    if (!opt.out.empty()) {
        file.open(opt.out + ".tmp");
        if (!file) {
            std::fprintf(stderr, "raykit_bench: cannot write %s.tmp\n", opt.out.c_str());
            return 1;
        }
    }
    int status = 1;
    try {
        status = run(opt, argv[0], file);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "raykit_bench: %s\n", e.what());
    }
    if (status != 0 && !opt.out.empty()) {
        file.close();
        std::remove((opt.out + ".tmp").c_str());
    }
    return status;
}
