/// \file unit_sphere.hpp
/// \brief Step 01: the unit sphere at the origin.
///
/// You write these two functions in `steps/01_unit_sphere/unit_sphere.cpp`.
/// Lecture: `lectures/01-unit-sphere.md`.
#pragma once

#include <optional>

#include "raykit/ray.hpp"
#include "raykit/roots.hpp"

namespace raykit {

/// Every `t` at which the line of \p ray meets the unit sphere
/// `x.x = 1`.
///
/// Substituting the ray into the sphere gives
/// `(d.d) t^2 + 2(o.d) t + (o.o - 1) = 0`.
///
/// \param ray any ray; its direction need not be unit length.
/// \return the real roots, sorted (see Roots): `count == 2` when the line
///         passes through, `count == 1` with `t[0] == t[1]` when it is tangent
///         (discriminant exactly zero), `count == 0` when it misses or when
///         the direction is zero. Inputs containing NaN or infinity count as a
///         miss; no root is ever NaN. Roots behind the origin (`t < 0`) are
///         included: this function knows nothing of windows.
///
/// Long and short directions, the same rule as sphere_roots(): any direction
/// whose `d.d` is a normal float (a length from about 1.1e-19 to 1.8e19:
/// 1e-7, 2^-60, or (2^-60, 1e-40, -1e-40), whose subnormal components change
/// nothing) is a ray, and its roots are asked for (t counts steps of `d`: a
/// short direction gives large roots). A direction so large that `d.d`
/// overflows float, or so small that `d.d` underflows to 0 in float, may
/// count as a miss, or give its true roots, computed in a wider type
/// (double): where they are representable in float, computing them in double
/// is right too. `d.d` is 0 for lengths below about 2.6e-23, and always when
/// every component is subnormal. Lengths from about 2.6e-23 to 1.1e-19 give
/// a `d.d` that is subnormal, not 0, with too few bits to follow the ray in
/// float: there too both answers are right, no roots or the true roots.
Roots unit_sphere_roots(const Ray& ray);

/// The closest hit of \p ray with the unit sphere inside the closed window
/// `tmin <= t <= tmax`.
///
/// \param ray  any ray; its direction need not be unit length.
/// \param tmin smallest accepted `t` (inclusive).
/// \param tmax largest accepted `t` (inclusive).
/// \return the smallest root `t` with `tmin <= t <= tmax`, or no value.
///         A root exactly at either end counts. When the near root is outside
///         the window but the far one is inside (a ray that starts inside the
///         sphere, for instance), the far root is returned. `tmin > tmax`
///         means an empty window: no value.
std::optional<float> intersect_unit_sphere(const Ray& ray, float tmin, float tmax);

}  // namespace raykit
