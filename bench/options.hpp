// The benchmark's command line (bench/reference/main.cpp).
#pragma once

#include <cstddef>
#include <string>

namespace raykit::bench {

/// What the command line asked for (see --help).
struct Options {
    std::size_t rays = 50000;    // per family, for the error pass
    int repetitions = 11;        // timed repetitions per variant and family (interleaved)
    double min_time = 0.003;     // seconds per repetition, about
    double peak_time = 0.02;     // seconds per run of a peak kernel
    bool subject_only = false;   // only the kit's sphere subject (the student build)
    std::string out;             // JSON file; stdout when empty
};

/// Parses the options; prints the usage and exits 2 on a bad one, 0 on --help.
Options parse_options(int argc, char** argv);

}  // namespace raykit::bench
