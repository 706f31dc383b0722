// This CPU's limits, measured on the spot: how many adds and multiplies one
// core retires per nanosecond in scalar code (how the formulations are
// compiled) and with every vector lane busy (the machine's peak), and how long
// a divide and a square root occupy the divider when many are in flight.
#pragma once

#include <string>

namespace raykit::bench {

struct Peak {
    double scalar_gflops_f32 = 0;   ///< scalar adds and multiplies, float, independent
    double scalar_gflops_f64 = 0;
    double vector_gflops_f32 = 0;   ///< widest vectors with FMA, float (0 when unsupported)
    double vector_gflops_f64 = 0;
    std::string vector_isa;         ///< e.g. "AVX2+FMA, 8 floats per FMA, 12 chains"
    double div_ns_f32 = 0, sqrt_ns_f32 = 0;  ///< ns each, many in flight (throughput)
    double div_ns_f64 = 0, sqrt_ns_f64 = 0;
};

/// Measures each rate: `repetitions` runs of about `seconds`, the best one
/// (a busy machine only ever slows a kernel down).
Peak measure_peak(double seconds, int repetitions);

/// This thread's CPU time in seconds: what the peak kernels are timed with, so
/// that a neighbour who takes the core away (the machine may be shared) does
/// not count as slowness of the kernel.
double thread_cpu_seconds();

/// A fixed amount of scalar arithmetic (about 50 us here), timed beside the
/// variants as the calibration job: its time puts two runs on one scale.
void calibration_pass();

/// The better of two measurements, rate by rate.
Peak best_of(const Peak& a, const Peak& b);

}  // namespace raykit::bench
