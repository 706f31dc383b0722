// The shortest text that reads back as the same float ("2", "0.5", "1.00000012"),
// for the grader's messages and for naming a call that crashed.
#pragma once

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace raykit {

inline std::string float_text(float x) {
    if (std::isnan(x)) return "NaN";
    if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
    char buf[64];
#if defined(__cpp_lib_to_chars)
    const auto end = std::to_chars(buf, buf + sizeof buf, x).ptr;  // shortest exact text
    return std::string(buf, end);
#else
    // GCC 10's library has no floating-point to_chars (Debian 11): the fewest significant digits
    // that read back as the same float. Nine always do (a float has a 24-bit significand).
    for (int digits = 1;; ++digits) {
        std::snprintf(buf, sizeof buf, "%.*g", digits, static_cast<double>(x));
        if (digits >= 9 || std::strtof(buf, nullptr) == x) return buf;
    }
#endif
}

}  // namespace raykit
