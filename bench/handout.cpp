// The benchmark of a student's handout: it measures your step 02's
// sphere_roots, and nothing else. The other rows of ./kit bench's table come
// from the committed reference run (docs/bench/results.json); ./kit bench puts
// your times on that run's scale with the calibration loop (peak.hpp), timed
// here and there. The error of your roots is measured against exact answers
// shipped as data (data/exact_roots.txt, written by the instructor's
// benchmark): no code here computes a root.
//
// The instructor's copy of the kit builds bench/reference/ instead, which
// measures every formulation (bench/CMakeLists.txt chooses).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "raykit/not_implemented.hpp"
#include "raykit/ray.hpp"
#include "raykit/roots.hpp"
#include "raykit/sphere.hpp"
#if RAYKIT_BENCH_SPHERE_STEP == 2
#include "raykit/general_sphere.hpp"
#endif

#include "families.hpp"
#include "options.hpp"
#include "peak.hpp"
#include "timing.hpp"

using namespace raykit::bench;

namespace {

constexpr std::size_t kBatch = 4096;  // as in the reference run

struct ExactRoots {
    bool hit = false, near_tangent = false;
    double t[2] = {0, 0};
};

struct ExactFamily {
    std::uint64_t fingerprint = 0;  // of the rays' inputs (families.hpp)
    std::vector<ExactRoots> rays;
};

/// data/exact_roots.txt: per family "= family rays fingerprint", then
/// "family index hit near_tangent t0 t1" per ray.
std::map<std::string, ExactFamily> read_exact(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error("cannot read the exact roots " + path);
    std::map<std::string, ExactFamily> out;
    std::string line;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#') continue;
        std::istringstream fields(line);
        if (line[0] == '=') {
            std::string mark, family, hex;
            std::size_t rays = 0;
            if (!(fields >> mark >> family >> rays >> hex)) throw std::runtime_error(path + ": unreadable line '" + line + "'");
            out[family].fingerprint = std::stoull(hex, nullptr, 16);
            continue;
        }
        std::string family;
        std::size_t index = 0;
        int hit = 0, near = 0;
        ExactRoots e;
        if (!(fields >> family >> index >> hit >> near >> e.t[0] >> e.t[1]) || index != out[family].rays.size()) {
            throw std::runtime_error(path + ": unreadable line '" + line + "'");
        }
        e.hit = hit != 0;
        e.near_tangent = near != 0;
        out[family].rays.push_back(e);
    }
    return out;
}

/// |got - exact| in float ulps at the exact value (exact given in double, which
/// resolves a float ulp to 2^-29 of itself).
double float_ulps(double exact, double got) {
    if (!std::isfinite(got)) return INFINITY;
    int e = 0;
    std::frexp(exact, &e);
    const int exponent = std::max(e - 1, -126);
    return std::fabs(got - exact) / std::ldexp(1.0, exponent - 23);
}

raykit::Roots subject(const raykit::Ray& ray, const raykit::Sphere& sphere) {
#if RAYKIT_BENCH_SPHERE_STEP == 2
    return raykit::sphere_roots(ray, sphere);
#else
    (void)ray;
    (void)sphere;
    return {};
#endif
}

struct Case {
    raykit::Ray ray;
    raykit::Sphere sphere;
};

std::string quote(const std::string& text) {
    std::string q = "\"";
    for (const char c : text) {
        if (c == '"' || c == '\\') q += '\\';
        if (static_cast<unsigned char>(c) >= 0x20) q += c;
    }
    return q + "\"";
}

std::string number(double x) {
    if (!std::isfinite(x)) return "null";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.9g", x);
    return buf;
}

double percentile(const std::vector<double>& sorted, double p) {
    if (sorted.empty()) return 0;
    const auto rank = static_cast<std::size_t>(std::ceil(p * static_cast<double>(sorted.size())));
    return sorted[std::min(sorted.size() - 1, rank == 0 ? 0 : rank - 1)];
}

std::vector<raykit::Roots> g_out(kBatch);

int run(const Options& opt, const char* argv0, std::ostream& os) {
    const auto exact = read_exact(RAYKIT_BENCH_EXACT_DATA);
    const std::size_t n = std::min<std::size_t>(opt.rays, kBatch);
    std::vector<SphereFamily> families = sphere_families(n);
    std::vector<std::vector<Case>> cases;
    for (const SphereFamily& f : families) {
        std::vector<Case> c;
        for (const Sample<float>& s : f.samples) {
            c.push_back({{{s.o.x, s.o.y, s.o.z}, {s.d.x, s.d.y, s.d.z}}, {{s.c.x, s.c.y, s.c.z}, s.r}});
        }
        cases.push_back(std::move(c));
    }

    std::string status = RAYKIT_BENCH_SPHERE_STEP == 2 ? "ok" : "absent";
    if (status == "ok") {
        try {
            subject(cases[0][0].ray, cases[0][0].sphere);
        } catch (const raykit::not_implemented&) {
            status = "not_started";
        } catch (const std::exception& e) {
            status = std::string("threw: ") + e.what();
        }
    }

    // The data must be for these very rays (a changed family needs new data).
    for (const SphereFamily& f : families) {
        const auto known = exact.find(f.id);
        if (known == exact.end()) throw std::runtime_error("data/exact_roots.txt has no family " + f.id);
        const std::size_t m = known->second.rays.size();
        if (f.samples.size() >= m && fingerprint(f.samples, m) != known->second.fingerprint) {
            throw std::runtime_error("data/exact_roots.txt holds the roots of other rays than bench/families.cpp "
                                     "makes for " + f.id + ": the instructor writes it again with "
                                     "raykit_bench --write-exact");
        }
    }

    // The error pass, over the rays whose exact roots were shipped.
    struct Row {
        std::string family;
        std::size_t rays = 0, in_band = 0, compared = 0, misclassified = 0;
        std::vector<double> errors;  // sorted
    };
    std::vector<Row> rows;
    std::vector<Job> jobs;
    try {
        for (std::size_t f = 0; f < families.size() && status == "ok"; ++f) {
            const auto known = exact.find(families[f].id);
            Row row;
            row.family = families[f].id;
            row.rays = std::min(known->second.rays.size(), cases[f].size());
            for (std::size_t i = 0; i < row.rays; ++i) {
                const ExactRoots& e = known->second.rays[i];
                if (e.near_tangent) {
                    ++row.in_band;
                    continue;
                }
                const raykit::Roots r = subject(cases[f][i].ray, cases[f][i].sphere);
                if ((r.count > 0) != e.hit) {
                    ++row.misclassified;
                } else if (e.hit) {
                    ++row.compared;
                    const double second = r.count == 1 ? r.t[0] : r.t[1];  // a tangent repeats its root
                    row.errors.push_back(std::max(float_ulps(e.t[0], r.t[0]), float_ulps(e.t[1], second)));
                }
            }
            std::sort(row.errors.begin(), row.errors.end());
            rows.push_back(std::move(row));
            const std::vector<Case>* batch = &cases[f];
            jobs.push_back({"kit/" + families[f].id,
                            [batch] {
                                for (std::size_t i = 0; i < batch->size(); ++i) {
                                    g_out[i] = subject((*batch)[i].ray, (*batch)[i].sphere);
                                }
                            },
                            batch->size()});
        }
    } catch (const raykit::not_implemented&) {
        status = "not_started", rows.clear(), jobs.clear();
    } catch (const std::exception& e) {
        status = std::string("threw: ") + e.what(), rows.clear(), jobs.clear();
    }
    jobs.push_back({kCalibration, calibration_pass, 1});
    const auto timings = time_jobs(jobs, opt.repetitions, opt.min_time, argv0);

    double calibration = NAN;
    if (const auto c = timings.find(kCalibration); c != timings.end() && !c->second.cpu_ns.empty()) {
        std::vector<double> v = c->second.cpu_ns;
        std::sort(v.begin(), v.end());
        calibration = v[v.size() / 2];
    }
    os << "{\n  \"meta\": {\"handout\": true, \"rays\": " << n << ", \"repetitions\": " << opt.repetitions
       << ", \"sphere_step\": " << RAYKIT_BENCH_SPHERE_STEP << ", \"calibration_ns\": " << number(calibration)
       << ", \"exact_rays\": \"the first rays of each family whose exact roots data/exact_roots.txt holds\"},\n"
       << "  \"variants\": [{\"id\": \"kit\", \"formulation\": \"kit\", \"label\": \"your step 02\", \"precision\": "
          "\"float\", \"group\": \"sphere\", \"ulp_of\": \"float\", \"lanes\": 1, \"isa\": \"\", \"status\": "
       << quote(status) << ", \"note\": \"sphere_roots(ray, sphere) of step 02\"}],\n  \"families\": [],\n"
       << "  \"results\": [\n";
    for (std::size_t k = 0; k < rows.size(); ++k) {
        const Row& r = rows[k];
        std::string times = "[";
        if (const auto t = timings.find("kit/" + r.family); t != timings.end()) {
            for (std::size_t i = 0; i < t->second.cpu_ns.size(); ++i) times += (i ? ", " : "") + number(t->second.cpu_ns[i]);
        }
        os << (k ? ",\n" : "") << "    {\"variant\": \"kit\", \"family\": " << quote(r.family) << ", \"rays\": " << r.rays
           << ", \"in_band\": " << r.in_band << ", \"compared\": " << r.compared
           << ", \"misclassified\": " << r.misclassified << ", \"ulps_median\": " << number(percentile(r.errors, 0.5))
           << ", \"ulps_p99\": " << number(percentile(r.errors, 0.99))
           << ", \"ulps_max\": " << number(r.errors.empty() ? 0 : r.errors.back())
           << ", \"flops\": null, \"div\": 0, \"sqrt\": 0, \"cpu_ns\": " << times << "], \"real_ns\": []}";
    }
    os << "\n  ]\n}\n";
    return os.good() ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
    const Options opt = parse_options(argc, argv);
    if (!opt.write_exact.empty()) {
        std::fprintf(stderr, "raykit_bench: --write-exact needs the instructor's benchmark (bench/reference/)\n");
        return 2;
    }
    try {
        if (opt.out.empty()) return run(opt, argv[0], std::cout);
        const std::string tmp = opt.out + ".tmp";
        int status = 1;
        {
            std::ofstream file(tmp);
            if (!file) {
                std::fprintf(stderr, "raykit_bench: cannot write %s\n", tmp.c_str());
                return 1;
            }
            status = run(opt, argv[0], file);
        }
        if (status != 0 || std::rename(tmp.c_str(), opt.out.c_str()) != 0) {
            std::remove(tmp.c_str());
            std::fprintf(stderr, "raykit_bench: writing %s failed\n", opt.out.c_str());
            return 1;
        }
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "raykit_bench: %s\n", e.what());
        if (!opt.out.empty()) std::remove((opt.out + ".tmp").c_str());
        return 1;
    }
}
