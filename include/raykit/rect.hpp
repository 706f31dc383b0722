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
/// It is the set of points `x` with `x[axis] == offset` whose two
/// other coordinates `(u, v)`, taken in increasing axis order, satisfy
/// `lo.x <= u <= hi.x` and `lo.y <= v <= hi.y` (edges and corners included):
///
/// | `axis` | plane             | `(u, v)` |
/// |--------|-------------------|--------------|
/// | 0      | `x = offset` | `(y, z)` |
/// | 1      | `y = offset` | `(x, z)` |
/// | 2      | `z = offset` | `(x, y)` |
///
/// So `Rect{1, 0, {0, 0}, {556, 559.2f}}` is the floor `y = 0` with
/// `0 <= x <= 556` and `0 <= z <= 559.2`.
///
/// A rectangle has no front or back: it is hit from either side. An `axis`
/// other than 0, 1 or 2, a `lo` greater than `hi` in either component, or a
/// NaN anywhere describes no rectangle: nothing hits it.
struct Rect {
    int axis;      ///< 0, 1 or 2: the plane is perpendicular to x, y or z.
    float offset;  ///< Where the plane crosses that axis: `x[axis] == offset`.
    glm::vec2 lo;  ///< Smallest `(u, v)`, the in-plane coordinates in increasing axis order.
    glm::vec2 hi;  ///< Largest `(u, v)`.
};

/// Where \p ray meets \p rect inside the closed window `tmin <= t <= tmax`.
///
/// The ray meets the plane `x[axis] == offset` at
/// `t = (offset - o[axis]) / d[axis]`; it is a hit
/// when that `t` is in the window and the point `o + t d`
/// lies in the rectangle.
///
/// \param ray  any ray; its direction need not be unit length.
/// \param rect any Rect (see there for the ones that describe nothing).
/// \param tmin smallest accepted `t` (inclusive).
/// \param tmax largest accepted `t` (inclusive).
/// \return that `t`, or no value. No value as well when the ray is
///         parallel to the plane (`direction[axis]` is `+0` or `-0`),
///         even when it lies in the plane: it then grazes the rectangle edge-on
///         and there is no single `t` to report. A point exactly on an edge
///         or a corner is a hit; `t` exactly at either end of the window
///         counts; `tmin > tmax` is an empty window. Never returns NaN.
std::optional<float> intersect_rect(const Ray& ray, const Rect& rect, float tmin, float tmax);

}  // namespace raykit
