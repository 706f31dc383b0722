// The visible tiers' rules, as yes/no answers, so that a hidden family can stop at
// its first failing draw and report only that one (in the visible tier's words).
#pragma once

#include <optional>

#include "../support/grading.hpp"

namespace raykit::hidden {

inline bool agree(const Roots& expected, const Roots& got) {
    if (got.count != expected.count) return false;
    if (got.count == 2 && !(got.t[0] <= got.t[1])) return false;
    if (got.count == 1 && !(got.t[0] == got.t[1])) return false;
    for (int i = 0; i < expected.count; ++i)
        if (!grading::close(expected.t[i], got.t[i])) return false;
    return true;
}

inline bool agree(const std::optional<float>& expected, const std::optional<float>& got) {
    return expected.has_value() == got.has_value() && (!expected || grading::close(*expected, *got));
}

}  // namespace raykit::hidden
