// Timing with Google Benchmark. See runner.hpp.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <random>

#include "timing.hpp"

namespace raykit::bench {

namespace {

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
#if RAYKIT_BENCHMARK_HAS_SKIPPED  // Google Benchmark 1.8 and later
            const bool failed = static_cast<int>(run.skipped) != 0;
            const std::string& why = run.skip_message;
#else  // 1.5 to 1.7
            const bool failed = run.error_occurred;
            const std::string& why = run.error_message;
#endif
            if (failed) {
                std::fprintf(stderr, "raykit_bench: %s: %s\n", name.c_str(), why.c_str());
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

}  // namespace

std::map<std::string, Timing> time_jobs(const std::vector<Job>& jobs, int repetitions, double seconds,
                                        const char* argv0) {
    std::map<std::string, Timing> timings;
    std::map<std::string, std::size_t> rays;
    // Every repetition is registered as a benchmark of its own, and the list
    // is shuffled (fixed seed): slow spells of a shared machine then spread
    // over every variant instead of hitting one. Doing it here rather than
    // with --benchmark_enable_random_interleaving (Google Benchmark 1.6 and
    // later) keeps 1.5 working too.
    struct One {
        const Job* job;
        benchmark::IterationCount iterations;
    };
    std::vector<One> order;
    for (const Job& job : jobs) {
        rays[job.name] = job.rays;
        // A fixed iteration count: Google Benchmark would otherwise search for
        // one before every repetition, which costs more than the measurement.
        const benchmark::IterationCount n = calibrate(job.pass, seconds);
        for (int r = 0; r < repetitions; ++r) order.push_back({&job, n});
    }
    std::mt19937 rng(20240501);
    std::shuffle(order.begin(), order.end(), rng);
    for (const One& one : order) {
        const auto pass = one.job->pass;
        benchmark::RegisterBenchmark(one.job->name.c_str(),
                                     [pass](benchmark::State& state) {
                                         for (auto _ : state) {
                                             pass();
                                             benchmark::ClobberMemory();
                                         }
                                     })
            ->Iterations(one.iterations)
            ->Unit(benchmark::kNanosecond);
    }
    std::string program = argv0;
    char* args[] = {program.data(), nullptr};
    int count = 1;
    benchmark::Initialize(&count, args);
    Collector collector(timings, rays, order.size());
    benchmark::RunSpecifiedBenchmarks(&collector);
    return timings;
}

}  // namespace raykit::bench
