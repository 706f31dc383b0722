/// \file ray.hpp
/// \brief A ray: a start point and a direction.
///
/// The formulas in these headers are plain text, as in code: `o.d` is the dot
/// product of `o` and `d`, `|d|` a length, `g x u` a cross product, `t^2` a
/// square. The lectures typeset the same formulas.
#pragma once

// Every step computes with these (std::sqrt, the float limits, glm::dot and glm::length), so the
// ray brings them. A graded compile reads the step header precompiled (tools/raykit/studentpch.py),
// and what the header includes comes with it at no cost: a step file then compiles in 0.07 s of
// CPU instead of 0.2 s (GCC 12, measured), where it would otherwise read <cmath> and GLM again.
#include <cmath>
#include <limits>

// The standard headers a step may use without including them itself, the same on every standard
// library. libc++ (a Mac's) and libstdc++ (the grader's, on Linux) pull different headers into one
// another, so a file using std::min_element, std::clamp, std::tuple or std::memcpy without its
// include compiled on one and not on the other: one verdict must not depend on that. Included
// here, they come with the precompiled step header in a graded compile.
// Not <functional>: with GCC 12 in C++17 it reads <unordered_map> for its searchers, 0.19 s of
// CPU of the 0.56 s a step file takes to compile (measured), paid at every check of the file,
// for std::function, which no step needs. A file using it without the include is told the
// header in the student's own check and in the grader's error (tools/raykit/includes.py), as
// for any name outside this list.
// The kit's own files (the judges, the dispatchers, the reference: CMakeLists.txt defines
// RAYKIT_KIT_OWN_FILE for them) include what they use themselves and skip these, which cost
// 0.14 s of CPU per file to read, four files on a cold check of step 01.
#if !defined(RAYKIT_KIT_OWN_FILE)
#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <numeric>
#include <optional>
#include <tuple>
#include <utility>
#include <vector>

// abs on a float, unqualified, is found the same on every standard library. libc++'s <stdlib.h>
// and <math.h> (a Mac's) declare float and double overloads of abs in the global namespace, so
// `abs(da)` with da = -0.5f is 0.5 there; libstdc++'s <cstdlib> (the grader's, on Linux) declares
// only C's int abs there, so the same call converts to int and gives 0, and one file got two
// verdicts. This is the declaration the standard's <stdlib.h> and <math.h> make on both libraries
// (libstdc++'s own <stdlib.h> reads `using std::abs;`): in the global namespace, and not in
// raykit's, it reaches a helper outside namespace raykit too, and a student's own abs(float) in
// namespace raykit still hides it instead of clashing with it. min and max need nothing: neither
// library declares them outside std, so an unqualified min(a, b) on floats does not compile on
// either (measured with GCC 12 and libstdc++, clang 14 and libc++), one verdict.
using std::abs;
#endif

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace raykit {

/// A ray is the set of points `p(t) = o + t d`.
///
/// - `origin` is `o`, in scene units.
/// - `direction` is `d`. It need **not** be unit length: a
///   distance along the ray is `t |d|`, so `t` counts
///   multiples of `d`, not scene units. A zero direction is a
///   degenerate ray that hits nothing.
///
/// Negative `t` are points behind the origin; the intersection functions
/// report them in their root lists but a window `tmin >= 0` excludes them.
struct Ray {
    glm::vec3 origin;     ///< `o`, where the ray starts.
    glm::vec3 direction;  ///< `d`, any length but zero.
};

/// The point `o + t d` on \p ray.
///
/// \param ray the ray; its direction need not be unit length.
/// \param t   how many multiples of the direction to go from the origin;
///             negative values go backwards, behind the origin.
/// \return the point, in scene units.
inline glm::vec3 point_at(const Ray& ray, float t) {
    return ray.origin + t * ray.direction;
}

}  // namespace raykit
