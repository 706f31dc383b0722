// The benchmark's results as JSON. See runner.hpp.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>

#include "runner.hpp"

namespace raykit::bench {

namespace {

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

/// The first value of `key` in /proc/cpuinfo, or "unknown". The file is read
/// once: its first processor's keys (the first value of each) are kept.
std::string cpuinfo(const std::string& key) {
    static const std::map<std::string, std::string> first = [] {
        std::map<std::string, std::string> values;
        std::ifstream in("/proc/cpuinfo");
        std::string line;
        while (std::getline(in, line)) {
            const auto colon = line.find(':');
            if (colon == std::string::npos) continue;
            std::string name = line.substr(0, colon);
            name.erase(name.find_last_not_of(" \t") + 1);
            values.emplace(name, colon + 2 <= line.size() ? line.substr(colon + 2) : "");  // keeps the first
        }
        return values;
    }();
    const auto it = first.find(key);
    return it == first.end() ? "unknown" : it->second;
}

std::string cpu_model() { return cpuinfo("model name"); }

/// "family 26, model 2, stepping 1": a virtual machine's model name can hide
/// which processor it runs on (both CPUs of the committed runs called
/// themselves "AMD EPYC"), and a change of host changes every time.
std::string cpu_id() {
    return "family " + cpuinfo("cpu family") + ", model " + cpuinfo("model") + ", stepping " + cpuinfo("stepping");
}

/// The median CPU time of the calibration pass, or NaN when it was not timed.
double calibration_ns(const std::map<std::string, Timing>& timings) {
    const auto t = timings.find(kCalibration);
    if (t == timings.end() || t->second.cpu_ns.empty()) return std::nan("");
    std::vector<double> v = t->second.cpu_ns;
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

std::string build_flags() {
#ifdef RAYKIT_BENCH_FLAGS
    return RAYKIT_BENCH_FLAGS;
#else
    return "";
#endif
}

}  // namespace

void write_json(std::ostream& os, const Options& opt, const Peak& peak, const std::vector<simd::Target>& targets,
                const std::vector<SphereData>& spheres,
                const std::vector<BoxData>& boxes, const std::vector<Variant>& variants, const std::vector<Row>& rows,
                const std::map<std::string, Timing>& timings) {
    const auto& cpu = benchmark::CPUInfo::Get();
    os << "{\n  \"meta\": {";
    os << "\"cpu\": " << quote(cpu_model()) << ", \"cpu_id\": " << quote(cpu_id()) << ", \"cpus\": " << cpu.num_cpus
       << ", \"mhz\": " << number(cpu.cycles_per_second / 1e6) << ", \"load_avg\": " << numbers(cpu.load_avg)
       << ", \"compiler\": " << quote(__VERSION__) << ", \"flags\": " << quote(build_flags())
       << ", \"rays\": " << opt.rays << ", \"batch\": " << batch_size(opt.rays)
       << ", \"repetitions\": " << opt.repetitions << ", \"min_time\": " << number(opt.min_time)
       << ", \"tangent_band\": " << number(kTangentBand) << ", \"edge_band\": " << number(kEdgeBand)
       << ", \"embree\": " << quote(embree::status()) << ", \"highway\": " << quote(simd::status()) << ", \"sphere_step\": " << kit::sphere_step()
       << ", \"rect_step\": " << (kit::has_rect() ? "true" : "false")
       << ", \"scene_step\": " << (kit::has_scene() ? "true" : "false")
       << ", \"calibration_ns\": " << number(calibration_ns(timings)) << "},\n";
    os << "  \"peak\": {\"scalar_gflops_f32\": " << number(peak.scalar_gflops_f32)
       << ", \"scalar_gflops_f64\": " << number(peak.scalar_gflops_f64)
       << ", \"vector_gflops_f32\": " << number(peak.vector_gflops_f32)
       << ", \"vector_gflops_f64\": " << number(peak.vector_gflops_f64) << ", \"vector_isa\": " << quote(peak.vector_isa)
       << ", \"div_ns_f32\": " << number(peak.div_ns_f32) << ", \"sqrt_ns_f32\": " << number(peak.sqrt_ns_f32)
       << ", \"div_ns_f64\": " << number(peak.div_ns_f64) << ", \"sqrt_ns_f64\": " << number(peak.sqrt_ns_f64)
       << ", \"vector_targets\": [";
    for (std::size_t i = 0; i < targets.size(); ++i) {
        const simd::Target& t = targets[i];
        os << (i ? ", " : "") << "{\"isa\": " << quote(t.name) << ", \"lanes_f32\": " << t.lanes_f32
           << ", \"lanes_f64\": " << t.lanes_f64 << ", \"gflops_f32\": " << number(t.gflops_f32)
           << ", \"gflops_f64\": " << number(t.gflops_f64) << ", \"div_ns_f32\": " << number(t.div_ns_f32)
           << ", \"div_ns_f64\": " << number(t.div_ns_f64) << ", \"sqrt_ns_f32\": " << number(t.sqrt_ns_f32)
           << ", \"sqrt_ns_f64\": " << number(t.sqrt_ns_f64) << ", \"cvt_ns\": " << number(t.cvt_ns)
           << ", \"shared_fma_cvt\": " << number(t.shared_fma_cvt)
           << ", \"shared_div_sqrt\": " << number(t.shared_div_sqrt) << "}";
    }
    os << "]},\n";
    os << "  \"families\": [\n";
    bool first = true;
    for (const auto& s : spheres) {
        os << (first ? "" : ",\n") << "    {\"id\": " << quote(s.family.id) << ", \"label\": " << quote(s.family.label)
           << ", \"group\": \"sphere\", \"hard\": " << (s.family.hard ? "true" : "false")
           << ", \"tangent_band\": " << number(s.family.tangent_band)
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
           << ", \"lanes\": " << v.lanes << ", \"isa\": " << quote(v.isa)
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
           << ", \"sqrt\": " << number(r.sqrt) << ", \"fma\": " << number(r.fma)
           << ", \"cvt\": " << r.variant->conversions;
        if (t != timings.end()) {
            os << ", \"cpu_ns\": " << numbers(t->second.cpu_ns) << ", \"real_ns\": " << numbers(t->second.real_ns);
        } else {
            os << ", \"cpu_ns\": [], \"real_ns\": []";
        }
        os << "}";
    }
    os << "\n  ]\n}\n";
}

}  // namespace raykit::bench
