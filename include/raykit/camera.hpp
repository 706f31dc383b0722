/// \file camera.hpp
/// \brief Step 05: a pinhole camera.
///
/// The view ray through a pixel, view_ray(), is declared in render.hpp: you
/// write it in `steps/05_cornell_box/render.cpp`.
/// Lecture: `lectures/05-cornell-box.md`.
#pragma once

#include "raykit/ray.hpp"

namespace raykit {

/// A pinhole camera: an eye, and a film in front of it divided into pixels.
///
/// The film is a rectangle perpendicular to `forward`, at distance
/// `focal_length` from the eye, centred on the line of sight. It is
/// `film_height` tall and `film_height * width / height` wide, so pixels are
/// square whatever the image's aspect ratio. Only the ratio
/// `film_height / focal_length` matters (it sets the field of view), so any
/// unit will do as long as both use the same.
///
/// The image's "right" is `r = g x u`
/// (forward, the gaze `g`, cross up): a camera looking along `+z` with up `+y` has
/// `-x` on its right.
struct Camera {
    glm::vec3 eye;       ///< The pinhole, where every view ray starts.
    glm::vec3 forward;   ///< Unit vector: where the camera looks (the image centre).
    glm::vec3 up;        ///< Unit vector perpendicular to `forward`: the image's up.
    float focal_length;  ///< Distance from the eye to the film, > 0.
    float film_height;   ///< Height of the film, > 0, in the same unit.
    int width;           ///< Image width in pixels, >= 1.
    int height;          ///< Image height in pixels, >= 1.
};

}  // namespace raykit
