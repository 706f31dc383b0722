/// \file scene.hpp
/// \brief Step 05: a scene of coloured rectangles, and a hit in it.
///
/// The closest hit in a scene, find_intersection(), is declared in render.hpp:
/// you write it in `steps/05_cornell_box/render.cpp`.
/// Lecture: `lectures/05-cornell-box.md`.
#pragma once

#include <cstddef>
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
/// that on a tie (two objects hit at the same `t`) the one listed first
/// is seen.
struct Scene {
    std::vector<Object> objects;  ///< The objects, tie order first to last.
};

/// Which object a ray hits first, and where.
struct Hit {
    float t;            ///< The ray parameter of the hit point `o + t d`.
    std::size_t index;  ///< The object hit: `scene.objects[index]`.
};

}  // namespace raykit
