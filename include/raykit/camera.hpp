/// \file camera.hpp
/// \brief Step 05: a pinhole camera, and the view ray through a pixel.
///
/// You write view_ray() in `steps/05_cornell_box/render.cpp`.
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
/// The image's "right" is \f$\mathbf{r} = \mathbf{f} \times \mathbf{u}\f$
/// (forward cross up): a camera looking along \f$+z\f$ with up \f$+y\f$ has
/// \f$-x\f$ on its right.
struct Camera {
    glm::vec3 eye;       ///< The pinhole, where every view ray starts.
    glm::vec3 forward;   ///< Unit vector: where the camera looks (the image centre).
    glm::vec3 up;        ///< Unit vector perpendicular to `forward`: the image's up.
    float focal_length;  ///< Distance from the eye to the film, > 0.
    float film_height;   ///< Height of the film, > 0, in the same unit.
    int width;           ///< Image width in pixels, >= 1.
    int height;          ///< Image height in pixels, >= 1.
};

/// The view ray through the centre of pixel (i, j): column \p i (0 at the
/// left), row \p j (0 at the **top**).
///
/// The pixel's centre on the film is
/// \f[ \mathbf{p} = \mathbf{e} + F\,\mathbf{f} + x\,\mathbf{r} + y\,\mathbf{u}, \quad
///     x = \Big(\frac{i + 1/2}{W} - \frac12\Big)\,w_\text{film}, \quad
///     y = \Big(\frac12 - \frac{j + 1/2}{H}\Big)\,h_\text{film} \f]
/// with \f$F\f$ the focal length, \f$\mathbf{r} = \mathbf{f} \times \mathbf{u}\f$,
/// \f$W \times H\f$ the image size and \f$w_\text{film} = h_\text{film} W / H\f$.
///
/// \param camera the camera, as documented in Camera.
/// \param i      the pixel's column, 0 at the left.
/// \param j      the pixel's row, 0 at the top.
/// \return a ray with origin `camera.eye` and a direction pointing from the
///         eye through that point: \f$\mathbf{p} - \mathbf{e}\f$ or any
///         positive multiple of it (normalised or not; the tests compare
///         directions, not lengths). Pixels outside the image are not an
///         error: they give rays beyond the film's edge.
Ray view_ray(const Camera& camera, int i, int j);

}  // namespace raykit
