/// \file rect.hpp
/// \brief Step 04: an axis-aligned rectangle, and where a ray meets it.
///
/// You write intersect_rect() in `steps/04_rectangles/rect.cpp`.
/// Lecture: `lectures/04-rectangles.md`.
#pragma once

#include <optional>

#include <glm/vec2.hpp>

#include "raykit/ray.hpp"

namespace raykit {

/// A rectangle lying in a plane perpendicular to one of the coordinate axes.
///
/// It is the set of points \f$\mathbf{x}\f$ with `x[axis] == offset` whose two
/// other coordinates \f$(u, v)\f$, taken in increasing axis order, satisfy
/// `lo.x <= u <= hi.x` and `lo.y <= v <= hi.y` (edges and corners included):
///
/// | `axis` | plane             | \f$(u, v)\f$ |
/// |--------|-------------------|--------------|
/// | 0      | \f$x = \f$ offset | \f$(y, z)\f$ |
/// | 1      | \f$y = \f$ offset | \f$(x, z)\f$ |
/// | 2      | \f$z = \f$ offset | \f$(x, y)\f$ |
///
/// So `Rect{1, 0, {0, 0}, {556, 559.2f}}` is the floor \f$y = 0\f$ with
/// \f$0 \le x \le 556\f$ and \f$0 \le z \le 559.2\f$.
///
/// A rectangle has no front or back: it is hit from either side. An `axis`
/// other than 0, 1 or 2, a `lo` greater than `hi` in either component, or a
/// NaN anywhere describes no rectangle: nothing hits it.
struct Rect {
    int axis;      ///< 0, 1 or 2: the plane is perpendicular to x, y or z.
    float offset;  ///< Where the plane crosses that axis: `x[axis] == offset`.
    glm::vec2 lo;  ///< Smallest \f$(u, v)\f$, the in-plane coordinates in increasing axis order.
    glm::vec2 hi;  ///< Largest \f$(u, v)\f$.
};

/// Where \p ray meets \p rect inside the closed window \f$ t_\min \le t \le t_\max \f$.
///
/// The ray meets the plane `x[axis] == offset` at
/// \f$ t = (\text{offset} - o_\text{axis}) / d_\text{axis} \f$; it is a hit
/// when that \f$t\f$ is in the window and the point \f$\mathbf{o} + t\,\mathbf{d}\f$
/// lies in the rectangle.
///
/// \param ray  any ray; its direction need not be unit length.
/// \param rect any Rect (see there for the ones that describe nothing).
/// \param tmin smallest accepted \f$t\f$ (inclusive).
/// \param tmax largest accepted \f$t\f$ (inclusive).
/// \return that \f$t\f$, or no value. No value as well when the ray is
///         parallel to the plane (`direction[axis]` is \f$+0\f$ or \f$-0\f$),
///         even when it lies in the plane: it then grazes the rectangle edge-on
///         and there is no single \f$t\f$ to report. A point exactly on an edge
///         or a corner is a hit; \f$t\f$ exactly at either end of the window
///         counts; `tmin > tmax` is an empty window. Never returns NaN.
std::optional<float> intersect_rect(const Ray& ray, const Rect& rect, float tmin, float tmax);

}  // namespace raykit
