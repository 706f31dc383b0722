// Timing with Google Benchmark, and the progress lines ./kit bench reads.
#pragma once

#include <cstddef>
#include <cstdio>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace raykit::bench {

/// One line per step on stderr; ./kit bench turns these into its progress display.
inline void progress(const char* phase, std::size_t done, std::size_t total, const std::string& what) {
    std::fprintf(stderr, "progress %s %zu %zu %s\n", phase, done, total, what.c_str());
    std::fflush(stderr);
}

/// Per repetition: nanoseconds per ray, CPU time (the process's own time, so a
/// neighbour that takes the core away does not count) and wall-clock time.
struct Timing {
    std::vector<double> cpu_ns, real_ns;
};

struct Job {
    std::string name;   // variant/family
    std::function<void()> pass;
    std::size_t rays;
};

/// Times every job with Google Benchmark: `repetitions` runs of about
/// `seconds` each, interleaved at random. Keyed by Job::name.
std::map<std::string, Timing> time_jobs(const std::vector<Job>& jobs, int repetitions, double seconds,
                                        const char* argv0);

/// The name of the calibration job: a fixed loop of arithmetic (peak.hpp)
/// timed with everything else, so that two runs, on two machines or two
/// days, can be put on one scale.
constexpr const char* kCalibration = "calibration";

}  // namespace raykit::bench
