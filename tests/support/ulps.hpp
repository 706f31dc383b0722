// Distance between two floats in units in the last place (ulps).
//
// Two floats are n ulps apart when n - 1 floats lie strictly between them.
// It is a relative measure: 1 ulp is 2^-23 of the value near 1, 2^-10 near
// 10^4, 2^-33 near 10^-3. No doctest here: the benchmark includes this file too.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace raykit::grading {

/// The floats in order as integers: consecutive floats get consecutive
/// integers, and +0 and -0 both map to 0.
inline std::int64_t ordered_bits(float x) {
    std::int32_t bits;
    std::memcpy(&bits, &x, sizeof bits);
    // Negative floats store their magnitude with the sign bit set: mirror them.
    return bits >= 0 ? std::int64_t{bits}
                     : std::int64_t{std::numeric_limits<std::int32_t>::min()} - bits;
}

/// How many ulps apart \p a and \p b are; the largest int64 when either is NaN.
inline std::int64_t ulp_distance(float a, float b) {
    if (std::isnan(a) || std::isnan(b)) return std::numeric_limits<std::int64_t>::max();
    const std::int64_t d = ordered_bits(a) - ordered_bits(b);
    return d < 0 ? -d : d;
}

}  // namespace raykit::grading
