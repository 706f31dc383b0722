// This CPU's peak, measured. See peak.hpp.
//
// Each kernel keeps many independent operations in flight so that it is
// limited by how many the core can start per cycle, not by how long one takes:
// 12 chains of "x = x * m + k" (a multiply and an add each step), 12 chains of
// vector FMAs, 8 chains of divides or square roots. m and k come from a
// volatile, so the compiler cannot fold the loops away, and the results are
// written to a volatile sink. The inner loops are unrolled completely so the
// chains live in registers (16 on x86-64: 12 chains, m and k) rather than in
// memory, where store-to-load forwarding would set the pace.

#include "peak.hpp"

#include <algorithm>
#include <cmath>
#include <ctime>

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#include <immintrin.h>
#define RAYKIT_BENCH_AVX2 1
#else
#define RAYKIT_BENCH_AVX2 0
#endif

#if defined(__GNUC__) && !defined(__clang__)
// Keep the scalar kernels scalar: at -O2 GCC may pack the 12 chains into SSE
// vectors, which would measure the vector rate instead.
#define RAYKIT_SCALAR __attribute__((noinline, optimize("no-tree-vectorize", "no-tree-slp-vectorize")))
#else
#define RAYKIT_SCALAR __attribute__((noinline))
#endif

namespace raykit::bench {

namespace {

volatile double g_seed = 0.999999;
volatile double g_sink = 0;

/// Runs kernel(iterations) for about `seconds`, `repetitions` times, and
/// returns the best rate: operations per nanosecond.
template <class Kernel>
double best_rate(Kernel kernel, double ops_per_iteration, double seconds, int repetitions) {
    long n = 1000;
    for (;;) {  // find an iteration count that takes about `seconds`
        const double t0 = thread_cpu_seconds();
        kernel(n);
        const double s = thread_cpu_seconds() - t0;
        if (s > seconds / 4 || n > (1L << 40)) {
            n = static_cast<long>(static_cast<double>(n) * std::max(1.0, seconds / std::max(s, 1e-9)));
            break;
        }
        n *= 4;
    }
    double best = 0;
    for (int rep = 0; rep < repetitions; ++rep) {
        const double t0 = thread_cpu_seconds();
        kernel(n);
        const double ns = 1e9 * (thread_cpu_seconds() - t0);
        best = std::max(best, ops_per_iteration * static_cast<double>(n) / ns);
    }
    return best;
}

template <class T>
RAYKIT_SCALAR void scalar_mul_add(long n) {
    const T m = static_cast<T>(g_seed), k = static_cast<T>(1 - g_seed);
    T x[12];
    for (int i = 0; i < 12; ++i) x[i] = static_cast<T>(i) * T(0.01) + T(1);
    for (long it = 0; it < n; ++it) {
#pragma GCC unroll 12
        for (int i = 0; i < 12; ++i) x[i] = x[i] * m + k;  // stays near 1: no overflow, no denormal
    }
    T sum = 0;
    for (int i = 0; i < 12; ++i) sum += x[i];
    g_sink = static_cast<double>(sum);
}

template <class T>
RAYKIT_SCALAR void scalar_div(long n) {
    const T m = static_cast<T>(g_seed);
    T x[8];
    for (int i = 0; i < 8; ++i) x[i] = static_cast<T>(i) * T(0.01) + T(1);
    for (long it = 0; it < n; ++it) {
#pragma GCC unroll 8
        for (int i = 0; i < 8; ++i) x[i] = m / x[i];  // alternates between two values near 1
    }
    T sum = 0;
    for (int i = 0; i < 8; ++i) sum += x[i];
    g_sink = static_cast<double>(sum);
}

template <class T>
RAYKIT_SCALAR void scalar_sqrt(long n) {
    T x[8];
    for (int i = 0; i < 8; ++i) x[i] = static_cast<T>(g_seed) + static_cast<T>(i);
    for (long it = 0; it < n; ++it) {
#pragma GCC unroll 8
        for (int i = 0; i < 8; ++i) x[i] = std::sqrt(x[i]);  // tends to 1 and stays there
    }
    T sum = 0;
    for (int i = 0; i < 8; ++i) sum += x[i];
    g_sink = static_cast<double>(sum);
}

#if RAYKIT_BENCH_AVX2
__attribute__((noinline, target("avx2,fma"))) void vector_fma_f32(long n) {
    const __m256 m = _mm256_set1_ps(static_cast<float>(g_seed));
    const __m256 k = _mm256_set1_ps(static_cast<float>(1 - g_seed));
    __m256 x[12];
    for (int i = 0; i < 12; ++i) x[i] = _mm256_set1_ps(1.0f + 0.01f * static_cast<float>(i));
    for (long it = 0; it < n; ++it) {
#pragma GCC unroll 12
        for (int i = 0; i < 12; ++i) x[i] = _mm256_fmadd_ps(x[i], m, k);
    }
    __m256 sum = x[0];
    for (int i = 1; i < 12; ++i) sum = _mm256_add_ps(sum, x[i]);
    alignas(32) float lanes[8];
    _mm256_store_ps(lanes, sum);
    g_sink = lanes[0];
}

__attribute__((noinline, target("avx2,fma"))) void vector_fma_f64(long n) {
    const __m256d m = _mm256_set1_pd(g_seed);
    const __m256d k = _mm256_set1_pd(1 - g_seed);
    __m256d x[12];
    for (int i = 0; i < 12; ++i) x[i] = _mm256_set1_pd(1.0 + 0.01 * i);
    for (long it = 0; it < n; ++it) {
#pragma GCC unroll 12
        for (int i = 0; i < 12; ++i) x[i] = _mm256_fmadd_pd(x[i], m, k);
    }
    __m256d sum = x[0];
    for (int i = 1; i < 12; ++i) sum = _mm256_add_pd(sum, x[i]);
    alignas(32) double lanes[4];
    _mm256_store_pd(lanes, sum);
    g_sink = lanes[0];
}
#endif

}  // namespace

double thread_cpu_seconds() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

Peak measure_peak(double seconds, int repetitions) {
    auto rate = [&](auto kernel, double ops) { return best_rate(kernel, ops, seconds, repetitions); };
    Peak p;
    p.scalar_gflops_f32 = rate(scalar_mul_add<float>, 12 * 2);
    p.scalar_gflops_f64 = rate(scalar_mul_add<double>, 12 * 2);
    p.div_ns_f32 = 1 / rate(scalar_div<float>, 8);
    p.div_ns_f64 = 1 / rate(scalar_div<double>, 8);
    p.sqrt_ns_f32 = 1 / rate(scalar_sqrt<float>, 8);
    p.sqrt_ns_f64 = 1 / rate(scalar_sqrt<double>, 8);
#if RAYKIT_BENCH_AVX2
    if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) {
        // An FMA is two flops, on 8 floats or 4 doubles.
        p.vector_gflops_f32 = rate(vector_fma_f32, 12 * 8 * 2);
        p.vector_gflops_f64 = rate(vector_fma_f64, 12 * 4 * 2);
        p.vector_isa = "AVX2+FMA";
    }
#endif
    if (p.vector_isa.empty()) p.vector_isa = "none measured";
    return p;
}

void calibration_pass() { scalar_mul_add<float>(25000); }

Peak best_of(const Peak& a, const Peak& b) {
    Peak p = a;
    p.scalar_gflops_f32 = std::max(a.scalar_gflops_f32, b.scalar_gflops_f32);
    p.scalar_gflops_f64 = std::max(a.scalar_gflops_f64, b.scalar_gflops_f64);
    p.vector_gflops_f32 = std::max(a.vector_gflops_f32, b.vector_gflops_f32);
    p.vector_gflops_f64 = std::max(a.vector_gflops_f64, b.vector_gflops_f64);
    p.div_ns_f32 = std::min(a.div_ns_f32, b.div_ns_f32);
    p.div_ns_f64 = std::min(a.div_ns_f64, b.div_ns_f64);
    p.sqrt_ns_f32 = std::min(a.sqrt_ns_f32, b.sqrt_ns_f32);
    p.sqrt_ns_f64 = std::min(a.sqrt_ns_f64, b.sqrt_ns_f64);
    return p;
}

}  // namespace raykit::bench
