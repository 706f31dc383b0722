// The benchmark's command line. See options.hpp.

#include "options.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace raykit::bench {

namespace {

const char* kUsage =
    "usage: raykit_bench [--quick | --smoke] [--rays=N] [--repetitions=N] [--min-time=SECONDS]\n"
    "                    [--subject-only] [--out=FILE]\n"
    "\n"
    "Measures the error (against float128) and the speed of ray-sphere formulations,\n"
    "the kit's own step functions and Embree, and writes the results as JSON.\n"
    "  --quick           fewer rays and repetitions (a few seconds)\n"
    "  --smoke           a tiny run that only checks everything works\n"
    "  --rays=N          rays per family for the error pass (default 50000)\n"
    "  --repetitions=N   timed repetitions per variant and family (default 11)\n"
    "  --min-time=S      seconds each repetition runs, about (default 0.003)\n"
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

}  // namespace

Options parse_options(int argc, char** argv) {
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
            o.rays = 10000, o.repetitions = 5, o.min_time = 0.002, o.peak_time = 0.005;
        } else if (key == "--smoke") {
            no_value();
            o.rays = 300, o.repetitions = 1, o.min_time = 1e-4, o.peak_time = 2e-4;
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

}  // namespace raykit::bench
