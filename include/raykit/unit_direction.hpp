/// \file unit_direction.hpp
/// \brief Step 03: the shortcut for unit directions, and its geometric reading.
///
/// You write these two functions in `steps/03_unit_direction/unit_direction.cpp`.
/// Lecture: `lectures/03-unit-direction.md`.
#pragma once

#include "raykit/ray.hpp"
#include "raykit/roots.hpp"
#include "raykit/sphere.hpp"

namespace raykit {

/// sphere_roots() for a ray whose direction has length 1, from the simplified
/// quadratic.
///
/// With `|d| = 1` the coefficient of `t^2` is 1 and the roots are
/// `t = -h +- sqrt(h^2 - c')`, with `f = o - center` (the origin seen from the
/// sphere's centre), `h = f.d` and the constant term `c' = f.f - r^2`.
///
/// \param ray    **precondition:** `|ray.direction| == 1` up to float rounding
///               (a direction from `glm::normalize`). For any other direction the
///               roots are wrong, by design: this is the price of the shortcut.
/// \param sphere a radius that is not a positive finite number describes no
///               sphere: `count == 0`.
/// \return the real roots, with the same contract as sphere_roots(): sorted,
///         `count == 1` and `t[0] == t[1]` for a tangent, roots behind the
///         origin included; inputs containing NaN or infinity count as a miss
///         and no root is ever NaN.
Roots sphere_roots_unit_dir(const Ray& ray, const Sphere& sphere);

/// The same roots read off a drawing: project the centre onto the ray, then
/// use Pythagoras twice.
///
/// With `L = center - o` (the centre seen from the origin) and a unit direction:
/// `t_m = L.d` is where the ray passes closest to the centre,
/// `l_m^2 = |L|^2 - t_m^2` is the squared distance of the line from the centre,
/// `dt = sqrt(r^2 - l_m^2)` is half the chord, and the roots are `t_m -+ dt`.
///
/// \param ray    **precondition:** `|ray.direction| == 1` up to float rounding.
/// \param sphere as for sphere_roots_unit_dir().
/// \return the same roots as sphere_roots_unit_dir(), with the same contract.
Roots sphere_roots_geometric(const Ray& ray, const Sphere& sphere);

}  // namespace raykit
