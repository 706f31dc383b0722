/// \file scene.hpp
/// \brief Step 05: a scene of coloured rectangles, and the closest hit in it.
///
/// You write find_intersection() in `steps/05_cornell_box/render.cpp`.
/// Lecture: `lectures/05-cornell-box.md`.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "raykit/color.hpp"
#include "raykit/ray.hpp"
#include "raykit/rect.hpp"

namespace raykit {

/// One thing in a scene: a rectangle with a flat colour and a name.
struct Object {
    std::string name;  ///< What it is, e.g. "floor"; tests and messages use it.
    Rect shape;        ///< Where it is.
    Color color;       ///< The colour a view ray that hits it first sees.
};

/// Everything there is: a list of objects, in no particular order except
/// that on a tie (two objects hit at the same \f$t\f$) the one listed first
/// is seen.
struct Scene {
    std::vector<Object> objects;  ///< The objects, tie order first to last.
};

/// Which object a ray hits first, and where.
struct Hit {
    float t;            ///< The ray parameter of the hit point \f$\mathbf{o} + t\,\mathbf{d}\f$.
    std::size_t index;  ///< The object hit: `scene.objects[index]`.
};

/// The closest hit of \p ray over all objects of \p scene inside the closed
/// window \f$ t_\min \le t \le t_\max \f$.
///
/// Brute force: every object is tried with intersect_rect() (step 04), and
/// the smallest \f$t\f$ wins. On a tie the object listed first wins: a later
/// object replaces the best hit so far only when it is **strictly** nearer.
///
/// \param ray   any ray; its direction need not be unit length.
/// \param scene any scene, possibly empty.
/// \param tmin  smallest accepted \f$t\f$ (inclusive).
/// \param tmax  largest accepted \f$t\f$ (inclusive).
/// \return the smallest \f$t\f$ and the index of its object, or no value when
///         no object is hit in the window (always for an empty scene or
///         `tmin > tmax`).
std::optional<Hit> find_intersection(const Ray& ray, const Scene& scene, float tmin, float tmax);

}  // namespace raykit
