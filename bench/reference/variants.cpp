// The variants under test and how each one is called. See runner.hpp.
//
// Every variant is called out of line, one call per ray, as the kit's step
// functions are (they live in other translation units); results go to an
// array the compiler must write.

#include <optional>
#include <type_traits>

#include <memory>

#include "formulations.hpp"
#include "runner.hpp"

namespace raykit::bench {

// The formulations of lanes-inl.h on one number at a time: to count their
// arithmetic, and the float-only exact form as a scalar variant.
namespace lanes1 {
#include "lanes-inl.h"
}  // namespace lanes1

namespace {

template <class T>
using Ops1 = lanes1::ScalarOps<T, float>;

template <class T>
RootsOf<T> from_lanes(const lanes1::LaneRoots<T, bool>& r) {
    RootsOf<T> out;
    if (r.hit) out = {2, {r.t0, r.t1}};
    return out;
}

/// The float-only exact form, one ray per call (std::fma: a call into the C
/// library unless the compiler may use the FMA instruction).
template <class T>
RAYKIT_FORMULATION RootsOf<T> exact_float(const Sample<T>& s) {
    return from_lanes(lanes1::lanes_exact_float(Ops1<T>{}, s.o.x, s.o.y, s.o.z, s.d.x, s.d.y, s.d.z, s.c.x,
                                                s.c.y, s.c.z, s.r));
}

}  // namespace

namespace {

// Where timed results go; one of each, reused.
std::vector<RootsOf<float>> g_out_f(kBatch);
std::vector<RootsOf<double>> g_out_d(kBatch);
std::vector<raykit::Roots> g_out_kit(kBatch);
std::vector<BoxHit> g_out_box(kBatch);

template <class In, class Out, Out (*F)(const In&)>
__attribute__((noinline)) Out out_of_line(const In& in) {
    return F(in);
}

template <class T>
Answer from_roots(const RootsOf<T>& r) {
    Answer a;
    a.count = r.count;
    a.t[0] = static_cast<double>(r.t[0]);
    a.t[1] = static_cast<double>(r.t[1]);
    return a;
}

Answer from_box(const BoxHit& h) {
    Answer a;
    if (h.hit) {
        a.count = 1;
        a.t[0] = h.t;
        a.rect = h.rect;
    }
    return a;
}

template <class T, RootsOf<T> (*F)(const Sample<T>&), RootsOf<Counted<float>> (*C)(
                                                            const Sample<Counted<float>>&)>
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
        if constexpr (wide) return from_roots(out_of_line<Sample<T>, RootsOf<T>, F>((*d)[f].wide[i]));
        else return from_roots(out_of_line<Sample<T>, RootsOf<T>, F>((*d)[f].family.samples[i]));
    };
    v.pass = [d](std::size_t f) {
        const auto& fam = (*d)[f];
        const std::size_t n = batch_size(fam.family.samples.size());
        if constexpr (wide) {
            const Sample<double>* in = fam.wide.data();
            for (std::size_t i = 0; i < n; ++i) g_out_d[i] = out_of_line<Sample<T>, RootsOf<T>, F>(in[i]);
        } else {
            const Sample<float>* in = fam.family.samples.data();
            for (std::size_t i = 0; i < n; ++i) g_out_f[i] = out_of_line<Sample<T>, RootsOf<T>, F>(in[i]);
        }
    };
    v.count = [d](std::size_t f, std::size_t i) {
        op_count() = {};
        C(convert<Counted<float>>((*d)[f].family.samples[i]));
        return op_count();
    };
    return v;
}

}  // namespace

std::vector<Variant> sphere_variants(const std::vector<SphereData>& data, bool subject_only) {
    std::vector<Variant> out;
    if (subject_only) {
        // An anchor timed in both runs, so ./kit bench can put the student's
        // times, measured in another process, on the reference run's scale.
        out.push_back(formulation<float, stable<float>, stable<Counted<float>>>(data, "stable", "float"));
    } else {
        out.push_back(formulation<float, textbook<float>, textbook<Counted<float>>>(data, "textbook", "float"));
        out.push_back(formulation<double, textbook<double>, textbook<Counted<float>>>(data, "textbook", "double"));
        out.push_back(formulation<float, half_b<float>, half_b<Counted<float>>>(data, "half-b", "float"));
        out.push_back(formulation<double, half_b<double>, half_b<Counted<float>>>(data, "half-b", "double"));
        out.push_back(formulation<float, unit_dir<float>, unit_dir<Counted<float>>>(data, "unit-dir", "float"));
        out.push_back(formulation<double, unit_dir<double>, unit_dir<Counted<float>>>(data, "unit-dir", "double"));
        out.push_back(formulation<float, geometric<float>, geometric<Counted<float>>>(data, "geometric", "float"));
        out.push_back(formulation<double, geometric<double>, geometric<Counted<float>>>(data, "geometric", "double"));
        out.push_back(formulation<float, stable<float>, stable<Counted<float>>>(data, "stable", "float"));
        out.push_back(formulation<double, stable<double>, stable<Counted<float>>>(data, "stable", "double"));
        out.push_back(formulation<float, lagrange<float>, lagrange<Counted<float>>>(data, "lagrange", "float"));
        out.push_back(formulation<double, lagrange<double>, lagrange<Counted<float>>>(data, "lagrange", "double"));
        Variant eft = formulation<float, exact_float<float>, exact_float<Counted<float>>>(data, "exact-float", "float");
        eft.note = "float only: float-float (error-free) f, a, h, f x d, c and discriminant; std::fma";
        out.push_back(eft);
        for (Variant mixed : {formulation<float, in_double<half_b<double>>, half_b<Counted<float>>>(
                                  data, "half-b", ""),
                              formulation<float, in_double<stable<double>>, stable<Counted<float>>>(
                                  data, "stable", ""),
                              formulation<float, in_double<half_b_pair<double>>, half_b_pair<Counted<float>>>(
                                  data, "half-b-pair", ""),
                              formulation<float, in_double<lagrange<double>>, lagrange<Counted<float>>>(
                                  data, "lagrange", "")}) {
            mixed.id = mixed.formulation + "_f32_in_f64";
            mixed.label = mixed.formulation + ", double inside";
            mixed.precision = "float, double inside";
            out.push_back(mixed);
        }
    }

    // The kit's own function: step 02's sphere_roots, or step 01 after a move.
    Variant subject;
    subject.id = "kit";
    subject.formulation = "kit";
    subject.group = "sphere";
    subject.precision = "float";
    const int step = kit::sphere_step();
    subject.label = step == 2 ? "kit step 02" : "kit step 01, ray moved to the unit sphere";
    subject.note = step == 2   ? "sphere_roots(ray, sphere) of step 02"
               : step == 1 ? "step 02 is not in this kit yet: step 01's unit_sphere_roots after o' = (o - c)/r, "
                             "d' = d/r"
                           : "no sphere step is built";
    if (step == 0) subject.status = "absent";
    const auto* d = &data;
    subject.answer = [d](std::size_t f, std::size_t i) {
        const KitSample& s = (*d)[f].kit[i];
        const raykit::Roots r = kit::sphere_roots(s.ray, s.sphere);
        Answer a;
        a.count = r.count == 0 ? 0 : 2;  // a tangent (count 1) repeats its root in t[1]
        a.t[0] = r.t[0];
        a.t[1] = r.t[1];
        return a;
    };
    subject.pass = [d](std::size_t f) {
        const auto& fam = (*d)[f];
        const std::size_t n = batch_size(fam.kit.size());
        const KitSample* in = fam.kit.data();
        for (std::size_t i = 0; i < n; ++i) g_out_kit[i] = kit::sphere_roots(in[i].ray, in[i].sphere);
    };
    out.push_back(subject);

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
        if (!embree::available()) e.status = "absent";
        e.applies = [d](std::size_t f) { return (*d)[f].embree != nullptr; };  // one sphere per family only
        e.answer = [d](std::size_t f, std::size_t i) {
            const Sample<float>& s = (*d)[f].family.samples[i];
            return from_box(embree::intersect((*d)[f].embree, s.o, s.d, 0.0f));
        };
        e.pass = [d](std::size_t f) {
            const auto& fam = (*d)[f];
            const std::size_t n = batch_size(fam.family.samples.size());
            const Sample<float>* in = fam.family.samples.data();
            for (std::size_t i = 0; i < n; ++i) g_out_box[i] = embree::intersect(fam.embree, in[i].o, in[i].d, 0.0f);
        };
        out.push_back(e);
    }
    return out;
}

BoxHit own_brute_force(const BoxData& b, std::size_t i) {
    return brute_force<float>(b.o[i], b.d[i], b.table.data(), static_cast<int>(b.table.size()), 0.0f);
}

__attribute__((noinline)) BoxHit own_brute_force_call(const Vec3<float>& o, const Vec3<float>& d,
                                                          const Rect3* rects, int n) {
    return brute_force<float>(o, d, rects, n, 0.0f);
}

// The benchmark's own rectangle test behind one out-of-line call per rectangle, in the two
// shapes a library could give it: a std::optional<float> (the kit's interface) and a bool with
// t by reference. Same arithmetic as the loop above; only the call and the return differ.
__attribute__((noinline)) std::optional<float> rect_call_optional(const Vec3<float>& o, const Vec3<float>& d,
                                                                   const Rect3& r, float tmin, float tmax) {
    float t;
    if (hit_rect(o, d, r, tmin, tmax, t)) return t;
    return std::nullopt;
}

__attribute__((noinline)) bool rect_call_plain(const Vec3<float>& o, const Vec3<float>& d, const Rect3& r,
                                               float tmin, float tmax, float& t) {
    return hit_rect(o, d, r, tmin, tmax, t);
}

template <bool Optional>
BoxHit brute_force_calls(const Vec3<float>& o, const Vec3<float>& d, const Rect3* rects, int n) {
    BoxHit best;
    float tmax = std::numeric_limits<float>::infinity();
    for (int i = 0; i < n; ++i) {
        float t = 0;
        bool hit;
        if constexpr (Optional) {
            const std::optional<float> h = rect_call_optional(o, d, rects[i], 0.0f, tmax);
            hit = h.has_value();
            if (hit) t = *h;
        } else {
            hit = rect_call_plain(o, d, rects[i], 0.0f, tmax, t);
        }
        if (hit && (!best.hit || t < tmax)) {
            tmax = t;
            best = {true, i, t};
        }
    }
    return best;
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
        op_count() = {};
        const auto wide = [](const Vec3<float>& v) {
            return Vec3<Counted<float>>{v.x, v.y, v.z};
        };
        brute_force<Counted<float>>(wide(b.o[i]), wide(b.d[i]), b.table.data(),
                                             static_cast<int>(b.table.size()), 0.0f);
        return op_count();
    };
    out.push_back(own);

    // Where the kit's own loop loses its time: the same test as the loop above, one call per
    // rectangle, returning a bool (and t by reference) or a std::optional<float>.
    for (bool optional : {false, true}) {
        Variant call = base(optional ? "call_optional" : "call_plain", "brute force",
                            optional ? "one call per rectangle, optional" : "one call per rectangle, bool");
        call.note = optional ? "hit_rect behind an out-of-line call returning std::optional<float>"
                             : "hit_rect behind an out-of-line call returning bool, t by reference";
        const auto loop = optional ? &brute_force_calls<true> : &brute_force_calls<false>;
        call.answer = [d, loop](std::size_t f, std::size_t i) {
            const BoxData& b = (*d)[f];
            return from_box(loop(b.o[i], b.d[i], b.table.data(), static_cast<int>(b.table.size())));
        };
        call.pass = [d, loop](std::size_t f) {
            const BoxData& b = (*d)[f];
            const std::size_t n = batch_size(b.o.size());
            const int rects = static_cast<int>(b.table.size());
            for (std::size_t i = 0; i < n; ++i) g_out_box[i] = loop(b.o[i], b.d[i], b.table.data(), rects);
        };
        out.push_back(call);
    }

    Variant kit_rect = base("kit_rect", "kit", "kit step 04, intersect_rect over the table");
    kit_rect.note = "raykit::intersect_rect for each rectangle, window shrinking";
    if (!kit::has_rect()) kit_rect.status = "absent";
    kit_rect.answer = [d](std::size_t f, std::size_t i) {
        return from_box(kit::brute_force((*d)[f].kit_table, (*d)[f].rays[i], 0.0f));
    };
    kit_rect.pass = [d](std::size_t f) {
        const BoxData& b = (*d)[f];
        const std::size_t n = batch_size(b.rays.size());
        for (std::size_t i = 0; i < n; ++i) g_out_box[i] = kit::brute_force(b.kit_table, b.rays[i], 0.0f);
    };
    out.push_back(kit_rect);

    Variant scene = base("kit_scene", "kit", "kit step 05, find_intersection");
    scene.note = "raykit::find_intersection over raykit::cornell_box()";
    if (!kit::has_scene()) scene.status = "absent";
    scene.applies = [d](std::size_t f) { return (*d)[f].whole_box; };
    scene.answer = [d](std::size_t f, std::size_t i) { return from_box(kit::find_intersection((*d)[f].rays[i], 0.0f)); };
    scene.pass = [d](std::size_t f) {
        const BoxData& b = (*d)[f];
        const std::size_t n = batch_size(b.rays.size());
        for (std::size_t i = 0; i < n; ++i) g_out_box[i] = kit::find_intersection(b.rays[i], 0.0f);
    };
    out.push_back(scene);

    Variant e = base("embree_quads", "embree", "Embree quads");
    e.note = "rtcIntersect1 on one RTC_GEOMETRY_TYPE_QUAD geometry, one quad per rectangle";
    if (!embree::available()) e.status = "absent";
    e.answer = [d](std::size_t f, std::size_t i) {
        return from_box(embree::intersect((*d)[f].embree, (*d)[f].o[i], (*d)[f].d[i], 0.0f));
    };
    e.pass = [d](std::size_t f) {
        const BoxData& b = (*d)[f];
        const std::size_t n = batch_size(b.o.size());
        for (std::size_t i = 0; i < n; ++i) g_out_box[i] = embree::intersect(b.embree, b.o[i], b.d[i], 0.0f);
    };
    out.push_back(e);
    return out;
}

// ---- many rays at once ---------------------------------------------------------------

namespace {

// Where the vector variants' timed results go.
std::vector<float> g_lane_t0(kBatch + simd::kPad), g_lane_t1(kBatch + simd::kPad), g_lane_hit(kBatch + simd::kPad);

std::size_t padded(std::size_t n) { return (n + simd::kPad - 1) / simd::kPad * simd::kPad; }

/// A formulation of lanes-inl.h on one counted ray: what every lane does.
using LaneCount = OpCount (*)(const Sample<float>&);

template <lanes1::LaneRoots<Counted<float>, bool> (*F)(const Ops1<Counted<float>>&, Counted<float>, Counted<float>,
                                                       Counted<float>, Counted<float>, Counted<float>,
                                                       Counted<float>, Counted<float>, Counted<float>,
                                                       Counted<float>, Counted<float>)>
OpCount lane_count(const Sample<float>& s) {
    op_count() = {};
    F(Ops1<Counted<float>>{}, s.o.x, s.o.y, s.o.z, s.d.x, s.d.y, s.d.z, s.c.x, s.c.y, s.c.z, s.r);
    return op_count();
}

Variant sphere_lanes(const std::vector<SphereData>& data, const simd::Target& t, simd::SphereKernel kernel,
                     const std::string& formulation, bool wide, LaneCount count) {
    Variant v;
    v.formulation = formulation;
    v.group = "sphere";
    v.lanes = wide ? t.lanes_f64 : t.lanes_f32;
    v.isa = t.name;
    v.precision = wide ? "float, double inside" : "float";
    v.conversions = wide ? simd::kConversions : 0;
    v.id = formulation + (wide ? "_f32_in_f64" : "_f32") + "_x" + std::to_string(v.lanes) + "_" + t.name;
    v.label = formulation + ", " + std::to_string(v.lanes) + " lanes " + t.name;  // the type column says the rest
    v.note = "Highway, " + t.name + ": " + std::to_string(v.lanes) + (wide ? " doubles" : " floats") +
             " per vector, rays as a structure of arrays, one call per batch";
    const auto* d = &data;
    // The error pass reads answers one ray at a time: run the kernel once over
    // the whole family and keep what it wrote.
    struct Cache {
        std::vector<std::vector<float>> t0, t1, hit;
    };
    auto cache = std::make_shared<Cache>();
    cache->t0.resize(data.size()), cache->t1.resize(data.size()), cache->hit.resize(data.size());
    v.answer = [d, kernel, cache](std::size_t f, std::size_t i) {
        const simd::Rays& in = (*d)[f].lanes;
        if (cache->t0[f].empty()) {
            const std::size_t n = in.ox.size();
            cache->t0[f].resize(n), cache->t1[f].resize(n), cache->hit[f].resize(n);
            kernel(in, 0, n, cache->t0[f].data(), cache->t1[f].data(), cache->hit[f].data());
        }
        Answer a;
        if (cache->hit[f][i] > 0) {
            a.count = 2;
            a.t[0] = cache->t0[f][i];
            a.t[1] = cache->t1[f][i];
        }
        return a;
    };
    v.pass = [d, kernel](std::size_t f) {
        const simd::Rays& in = (*d)[f].lanes;
        kernel(in, 0, padded(batch_size(in.n)), g_lane_t0.data(), g_lane_t1.data(), g_lane_hit.data());
    };
    v.count = [d, count](std::size_t f, std::size_t i) { return count((*d)[f].family.samples[i]); };
    return v;
}

/// A whole-batch box query: `run(f, end, t, rect)` answers rays [0, end) of family f.
using BoxRun = std::function<void(std::size_t f, std::size_t end, float* t, float* rect)>;

/// The answer and the timed pass of a whole-batch box query. The error pass reads answers one ray at
/// a time: `run` goes once over the whole family and what it wrote is kept.
void set_box_answers(Variant& v, const std::vector<BoxData>& boxes, BoxRun run) {
    struct Cache {
        std::vector<std::vector<float>> t, rect;
    };
    auto cache = std::make_shared<Cache>();
    cache->t.resize(boxes.size()), cache->rect.resize(boxes.size());
    const auto* b = &boxes;
    v.answer = [b, run, cache](std::size_t f, std::size_t i) {
        if (cache->t[f].empty()) {
            const std::size_t n = (*b)[f].lanes.ox.size();
            cache->t[f].resize(n), cache->rect[f].resize(n);
            run(f, n, cache->t[f].data(), cache->rect[f].data());
        }
        Answer a;
        if (cache->rect[f][i] >= 0) {
            a.count = 1;
            a.t[0] = cache->t[f][i];
            a.rect = static_cast<int>(cache->rect[f][i]);
        }
        return a;
    };
    v.pass = [b, run](std::size_t f) {
        run(f, padded(batch_size((*b)[f].lanes.n)), g_lane_t0.data(), g_lane_hit.data());
    };
}

}  // namespace

std::vector<Variant> vector_variants(const std::vector<SphereData>& spheres, const std::vector<BoxData>& boxes,
                                     const std::vector<simd::Target>& targets) {
    std::vector<Variant> out;
    using C = Ops1<Counted<float>>;
    for (const simd::Target& t : targets) {
        out.push_back(sphere_lanes(spheres, t, t.lagrange_f64, "lagrange", true, &lane_count<&lanes1::lanes_lagrange<C>>));
        out.push_back(sphere_lanes(spheres, t, t.half_b_f64, "half-b", true, &lane_count<&lanes1::lanes_half_b<C>>));
        out.push_back(sphere_lanes(spheres, t, t.half_b_f32, "half-b", false, &lane_count<&lanes1::lanes_half_b<C>>));
        out.push_back(sphere_lanes(spheres, t, t.stable_f32, "stable", false, &lane_count<&lanes1::lanes_stable<C>>));
        out.push_back(sphere_lanes(spheres, t, t.exact_f32, "exact-float", false,
                                   &lane_count<&lanes1::lanes_exact_float<C>>));
    }
    const auto* b = &boxes;
    for (const simd::Target& t : targets) {
        Variant v;
        v.formulation = "brute force";
        v.group = "box";
        v.kind = Kind::box;
        v.precision = "float";
        v.lanes = t.lanes_f32;
        v.isa = t.name;
        v.id = "brute_force_x" + std::to_string(v.lanes) + "_" + t.name;
        v.label = "brute force, " + std::to_string(v.lanes) + " lanes " + t.name;
        v.note = "the same loop over the rectangles, across rays: each lane keeps its own window";
        const simd::BoxKernel kernel = t.box_f32;
        set_box_answers(v, boxes, [b, kernel](std::size_t f, std::size_t end, float* t_out, float* rect) {
            const BoxData& box = (*b)[f];
            kernel(box.lanes, 0, end, box.table.data(), static_cast<int>(box.table.size()), 0.0f, t_out, rect);
        });
        out.push_back(v);
    }
    // Embree's packet queries on the same quads, as many rays per call as the
    // widest vectors above hold (8 and 16 where this Embree runs them natively).
    for (const int width : {8, 16}) {
        Variant e;
        e.formulation = "embree";
        e.group = "box";
        e.kind = Kind::box;
        e.precision = "float";
        e.lanes = width;
        e.isa = "Embree";
        e.id = "embree_quads_x" + std::to_string(width);
        e.label = "Embree quads, rtcIntersect" + std::to_string(width);
        e.note = "rtcIntersect" + std::to_string(width) + " on the quads of the scalar Embree row, every lane active";
        if (!embree::packets(width)) {
            e.status = "absent";
            e.note = embree::available() ? "this Embree does not run packets of " + std::to_string(width) + " natively"
                                         : embree::status();
        }
        set_box_answers(e, boxes, [b, width](std::size_t f, std::size_t end, float* t, float* rect) {
            const BoxData& box = (*b)[f];
            const float* const o[3] = {box.lanes.ox.data(), box.lanes.oy.data(), box.lanes.oz.data()};
            const float* const d[3] = {box.lanes.dx.data(), box.lanes.dy.data(), box.lanes.dz.data()};
            embree::intersect_packets(box.embree, width, o, d, 0, end, 0.0f, t, rect);
        });
        out.push_back(e);
    }
    return out;
}

}  // namespace raykit::bench
