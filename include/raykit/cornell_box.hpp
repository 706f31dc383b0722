/// \file cornell_box.hpp
/// \brief Step 05: the empty Cornell box, modelled with axis-aligned rectangles.
///
/// You write these two functions in `steps/05_cornell_box/cornell_box.cpp`.
/// Lecture: `lectures/05-cornell-box.md`, which gives the numbers and where
/// they come from: the Cornell box data of the Cornell University Program of
/// Computer Graphics.
#pragma once

#include "raykit/camera.hpp"
#include "raykit/scene.hpp"

namespace raykit {

/// The empty Cornell box: six rectangles, in millimetres, with their colours.
///
/// The objects, each exactly once, with these names:
/// `"floor"`, `"ceiling"`, `"back wall"`, `"left wall"` (red), `"right wall"`
/// (green) and `"light"`; nothing else. "Left" and "right" are as seen from
/// the camera. The light lies in the ceiling's plane, so a view ray hits both
/// at the same `t`: list the light **before** the ceiling, so that it wins
/// the tie (see find_intersection()).
///
/// \return the six objects of the box, the light first.
Scene cornell_box();

/// The camera of the Cornell box data, for an image of \p width x \p height
/// pixels: eye `(278, 273, -800)`, looking along `+z` with up
/// `+y`, focal length 0.035 and film height 0.025 (metres).
///
/// \param width  image width in pixels, >= 1.
/// \param height image height in pixels, >= 1.
/// \return the camera, ready for view_ray() and render().
Camera cornell_camera(int width, int height);

}  // namespace raykit
