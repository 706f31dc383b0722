/// \file cornell_box_data.hpp
/// \brief The empty Cornell box's numbers (raykit/scenes/cornell_box.inc) as C++ values, for the
/// kit's own readers: the reference solution, the step 05 suites and the renderer.
#pragma once

#include <array>

#include "raykit/camera.hpp"
#include "raykit/scene.hpp"

namespace raykit::scenes::cornell {

/// The flat colours, by name.
#define RAYKIT_SCENE_COLOR(name, r, g, b) inline const Color name{r, g, b};
#include "raykit/scenes/cornell_box.inc"

/// One object of the box: its name, its rectangle and its colour.
struct Row {
    const char* name;
    Rect rect;
    Color color;
};

/// The six objects, in list order (the light first).
inline const std::array<Row, 6>& rows() {
    static const std::array<Row, 6> all{{
#define RAYKIT_SCENE_OBJECT(label, axis, offset, lo_u, lo_v, hi_u, hi_v, color) \
    Row{label, Rect{axis, offset, {lo_u, lo_v}, {hi_u, hi_v}}, color},
#include "raykit/scenes/cornell_box.inc"
    }};
    return all;
}

/// The camera of the data for an image of width x height pixels.
inline Camera camera(int width, int height) {
#define RAYKIT_SCENE_CAMERA(ex, ey, ez, fx, fy, fz, ux, uy, uz, focal_length, film_height) \
    return Camera{{ex, ey, ez}, {fx, fy, fz}, {ux, uy, uz}, focal_length, film_height, width, height};
#include "raykit/scenes/cornell_box.inc"
}

}  // namespace raykit::scenes::cornell
