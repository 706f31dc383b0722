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
/// With \f$|\mathbf{d}| = 1\f$ the coefficient of \f$t^2\f$ is 1 and the roots
/// are \f$ t = -h \pm \sqrt{h^2 - c} \f$, with \f$h = \mathbf{f}\cdot\mathbf{d}\f$,
/// \f$c = \mathbf{f}\cdot\mathbf{f} - r^2\f$ and \f$\mathbf{f} = \mathbf{o} - \mathbf{c}\f$.
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
/// With \f$\mathbf{L} = \mathbf{c} - \mathbf{o}\f$ and a unit direction:
/// \f$ t_m = \mathbf{L}\cdot\mathbf{d} \f$ is where the ray passes closest to the
/// centre, \f$ \ell_m^2 = |\mathbf{L}|^2 - t_m^2 \f$ is the squared distance of the
/// line from the centre, \f$ \Delta t = \sqrt{r^2 - \ell_m^2} \f$ is half the
/// chord, and the roots are \f$ t_m \mp \Delta t \f$.
///
/// \param ray    **precondition:** `|ray.direction| == 1` up to float rounding.
/// \param sphere as for sphere_roots_unit_dir().
/// \return the same roots as sphere_roots_unit_dir(), with the same contract.
Roots sphere_roots_geometric(const Ray& ray, const Sphere& sphere);

}  // namespace raykit
