/// \file general_sphere.hpp
/// \brief Step 02: a sphere anywhere, of any size.
///
/// You write these two functions in `steps/02_general_sphere/general_sphere.cpp`.
/// Lecture: `lectures/02-general-sphere.md`.
#pragma once

#include <optional>

#include "raykit/ray.hpp"
#include "raykit/roots.hpp"
#include "raykit/sphere.hpp"

namespace raykit {

/// Every `t` at which the line of \p ray meets \p sphere, `|x - center|^2 = r^2`.
///
/// With `f = o - center` (the origin seen from the centre), substituting the
/// ray gives `(d.d) t^2 + 2(f.d) t + (f.f - r^2) = 0`.
///
/// \param ray    any ray; its direction need not be unit length.
/// \param sphere any centre; a radius that is not a positive finite number
///               (zero, negative, NaN, infinite) describes no sphere.
/// \return the real roots, sorted (see Roots): `count == 2` when the line
///         passes through, `count == 1` with `t[0] == t[1]` when it is tangent
///         (discriminant exactly zero), `count == 0` when it misses, when the
///         direction is zero or when the radius describes no sphere. Inputs
///         containing NaN or infinity count as a miss; no root is ever NaN.
///         Roots behind the origin (`t < 0`) are included.
///
/// Long and short directions, the same rule as unit_sphere_roots(): any direction
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
///
/// The ★ robust cases also ask for accuracy: each root within a few units in
/// the last place (ulps) of the exact root of the same float inputs, for far,
/// tiny, huge and grazing configurations (lecture 03, sections 4 to 6).
Roots sphere_roots(const Ray& ray, const Sphere& sphere);

/// The closest hit of \p ray with \p sphere inside the closed window
/// `tmin <= t <= tmax`.
///
/// \param ray    any ray; its direction need not be unit length.
/// \param sphere as for sphere_roots().
/// \param tmin   smallest accepted `t` (inclusive).
/// \param tmax   largest accepted `t` (inclusive).
/// \return the smallest root `t` with `tmin <= t <= tmax`, or no value.
///         A root exactly at either end counts; when the near root is outside
///         the window but the far one is inside, the far root is returned;
///         `tmin > tmax` is an empty window.
std::optional<float> intersect_sphere(const Ray& ray, const Sphere& sphere, float tmin, float tmax);

}  // namespace raykit
