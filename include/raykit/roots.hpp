/// \file roots.hpp
/// \brief Where a line meets a surface: zero, one or two parameters t.
#pragma once

namespace raykit {

/// The parameters `t` at which the whole line `o + t d`
/// (both directions, `t in (-inf, inf)`) meets a sphere.
///
/// Contract, for every function that returns Roots:
/// - `count` is 0 (the line misses), 1 (it touches: a tangent) or 2 (it passes
///   through);
/// - `t[0] <= t[1]` always;
/// - for a tangent (`count == 1`) both entries hold the same root:
///   `t[0] == t[1]`;
/// - entries beyond `count` are not read by anyone; for `count == 0` they are 0.
struct Roots {
    int count = 0;           ///< How many roots: 0, 1 or 2.
    float t[2] = {0, 0};     ///< The roots, smallest first.
};

}  // namespace raykit
