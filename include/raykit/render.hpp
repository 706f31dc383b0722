/// \file render.hpp
/// \brief Step 05: render a scene, one view ray per pixel.
///
/// You write render() in `steps/05_cornell_box/render.cpp`.
/// Lecture: `lectures/05-cornell-box.md`.
#pragma once

#include "raykit/camera.hpp"
#include "raykit/canvas.hpp"
#include "raykit/scene.hpp"

namespace raykit {

/// The colour of a pixel whose view ray hits nothing: black.
inline constexpr Color background{0.0f, 0.0f, 0.0f};

/// The flat-colour picture of \p scene seen by \p camera.
///
/// For every pixel (i, j) of the `camera.width` x `camera.height` image:
/// take view_ray(camera, i, j), find its closest hit with
/// find_intersection() in the window \f$[0, \infty]\f$ (everything in front
/// of the eye), and paint the pixel with the colour of the object hit, or
/// with #background when nothing is hit.
///
/// \param scene  what to draw.
/// \param camera where it is seen from, and the image size.
/// \return a Canvas of `camera.width` x `camera.height` pixels.
Canvas render(const Scene& scene, const Camera& camera);

}  // namespace raykit
