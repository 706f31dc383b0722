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

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#if defined(__SSE2__)
#include <pmmintrin.h>
#include <xmmintrin.h>
#endif

#include "raykit/not_implemented.hpp"

#include "runner.hpp"

using namespace raykit::bench;

namespace {

// ---- setting up the families --------------------------------------------------------

std::vector<SphereData> make_spheres(std::size_t n, bool with_embree) {
    std::vector<SphereData> out;
    std::vector<SphereFamily> families = sphere_families(n);
    for (SphereFamily& f : families) {
        SphereData d;
        d.family = std::move(f);
        for (const Sample<float>& s : d.family.samples) {
            d.exact.push_back(exact_sphere(s, d.family.tangent_band));
            d.wide.push_back(convert<double>(s));
            d.kit.push_back({{{s.o.x, s.o.y, s.o.z}, {s.d.x, s.d.y, s.d.z}}, {{s.c.x, s.c.y, s.c.z}, s.r}});
        }
        d.lanes = simd::to_lanes(d.family.samples);
        // Embree gets one scene per family: only where every ray sees the same sphere.
        bool one_sphere = true;
        for (const Sample<float>& s : d.family.samples) {
            const Sample<float>& s0 = d.family.samples[0];
            one_sphere = one_sphere && s.r == s0.r && s.c.x == s0.c.x && s.c.y == s0.c.y && s.c.z == s0.c.z;
        }
        if (with_embree && one_sphere) d.embree = embree::sphere(d.family.samples[0].c, d.family.samples[0].r);
        progress("setup", out.size() + 1, families.size(), d.family.id);
        out.push_back(std::move(d));
    }
    return out;
}

std::vector<BoxData> make_boxes(std::size_t n, std::string& note) {
    std::vector<Rect3> box;
    try {
        box = kit::box_table();
    } catch (const std::exception& e) {
        note = std::string("cornell_box() failed (") + e.what() + "); the benchmark's own table is used";
        box.assign(kCornellBox, kCornellBox + kBoxRects);
    }
    // The back wall: the rectangle at z = 555, or else the last one.
    std::vector<Rect3> back_wall = {box.back()};
    for (const Rect3& r : box) {
        if (r.axis == 2 && r.offset > 500) back_wall = {r};
    }
    std::vector<BoxData> out;
    for (BoxFamily& f : box_families(n)) {
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
            b.exact.push_back(exact_box(b.o[i], b.d[i], b.table.data(), static_cast<int>(b.table.size()), 0.0f));
        }
        b.lanes = simd::to_lanes(b.o, b.d);
        if (embree::available()) b.embree = embree::quads(b.table);
        if (kit::has_rect()) b.kit_table = kit::rect_table(b.table);
    }
    return out;
}

/// Average operation counts over the timed batch, or -1 flops when unknown.
void count_ops(const Variant& v, std::size_t f, std::size_t n, Row& row) {
    if (!v.count) return;
    double flops = 0, div = 0, sqrt = 0, fma = 0;
    const std::size_t m = batch_size(n);
    for (std::size_t i = 0; i < m; ++i) {
        const OpCount c = v.count(f, i);
        flops += static_cast<double>(c.flops());
        div += static_cast<double>(c.div);
        sqrt += static_cast<double>(c.sqrt);
        fma += static_cast<double>(c.fma);
    }
    row.flops = flops / static_cast<double>(m);
    row.div = div / static_cast<double>(m);
    row.sqrt = sqrt / static_cast<double>(m);
    row.fma = fma / static_cast<double>(m);
}

/// Runs the error pass of the kit's subject once, to learn whether it is
/// written: a stub throws raykit::not_implemented.
void probe_subject(Variant& subject, const std::vector<SphereData>& spheres) {
    if (subject.status != "ok") return;
    try {
        for (std::size_t f = 0; f < spheres.size(); ++f) {
            for (std::size_t i = 0; i < spheres[f].family.samples.size(); ++i) subject.answer(f, i);
        }
    } catch (const raykit::not_implemented&) {
        subject.status = "not_started";
    } catch (const std::exception& e) {
        subject.status = std::string("threw: ") + e.what();
    }
}

int run(const Options& opt, const char* argv0, std::ofstream& file) {
#if defined(__SSE2__)
    // Embree asks for flush-to-zero and denormals-are-zero; no input or result
    // of this benchmark is a denormal, so the other variants are unaffected.
    _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
    _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
#endif
    const bool with_embree = !opt.subject_only && embree::available();
    std::vector<SphereData> spheres = make_spheres(opt.rays, with_embree);
    std::string box_note;
    std::vector<BoxData> boxes;
    if (!opt.subject_only) boxes = make_boxes(opt.rays, box_note);

    std::vector<Variant> variants = sphere_variants(spheres, opt.subject_only);
    for (Variant& v : variants) {
        if (v.id == "kit") probe_subject(v, spheres);
    }
    std::vector<simd::Target> targets;
    if (!opt.subject_only) {
        targets = simd::targets();
        for (Variant& v : vector_variants(spheres, boxes, targets)) variants.push_back(std::move(v));
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
            if (v.group != "sphere" || v.status != "ok" || !v.applies(f)) continue;
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

    jobs.push_back({kCalibration, calibration_pass, 1});

    // This CPU's peak, measured before and after the timing: the better of
    // the two, as a neighbour's work can only have slowed a kernel down.
    // Three runs of each kernel each time, six in all, of which the best
    // counts; five each time, as before, cost 2 x 2 runs x 22 kernels x
    // 20 ms = 1.8 s more.
    constexpr int kPeakRuns = 3;
    Peak peak;
    if (!opt.subject_only) {
        progress("peak", 0, 2, "");
        peak = measure_peak(opt.peak_time, kPeakRuns);
        for (simd::Target& t : targets) simd::measure(t, opt.peak_time, kPeakRuns);
    }
    const std::map<std::string, Timing> timings = time_jobs(jobs, opt.repetitions, opt.min_time, argv0);
    if (!opt.subject_only) {
        progress("peak", 1, 2, "");
        peak = best_of(peak, measure_peak(opt.peak_time, kPeakRuns));
        for (simd::Target& t : targets) simd::measure(t, opt.peak_time, kPeakRuns);
        progress("peak", 2, 2, "");
    }

    if (opt.out.empty()) {
        write_json(std::cout, opt, peak, targets, spheres, boxes, variants, rows, timings);
        return std::cout.good() ? 0 : 1;
    }
    write_json(file, opt, peak, targets, spheres, boxes, variants, rows, timings);
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
    const Options opt = parse_options(argc, argv);
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
