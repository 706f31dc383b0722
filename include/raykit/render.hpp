/// \file render.hpp
/// \brief Step 05: the closest hit, the view ray through a pixel, the render loop.
///
/// You write these three functions in `steps/05_cornell_box/render.cpp`. The
/// types they use are in scene.hpp (Scene, Hit) and camera.hpp (Camera).
/// Lecture: `lectures/05-cornell-box.md`.
#pragma once

#include <optional>

#include "raykit/camera.hpp"
#include "raykit/canvas.hpp"
#include "raykit/scene.hpp"

namespace raykit {

/// The closest hit of \p ray over all objects of \p scene inside the closed
/// window `tmin <= t <= tmax`.
///
/// Brute force: every object is tried with intersect_rect() (step 04), and
/// the smallest `t` wins: the first point along the ray in the window, which
/// for `tmin < 0` may lie behind the origin (then `t = -3` beats `t = 2`, though
/// it is farther from the origin). On a tie the object listed first wins: a later
/// object replaces the best hit so far only when it is **strictly** nearer.
///
/// \param ray   any ray; its direction need not be unit length.
/// \param scene any scene, possibly empty.
/// \param tmin  smallest accepted `t` (inclusive).
/// \param tmax  largest accepted `t` (inclusive).
/// \return the smallest `t` and the index of its object, or no value when
///         no object is hit in the window (always for an empty scene or
///         `tmin > tmax`).
std::optional<Hit> find_intersection(const Ray& ray, const Scene& scene, float tmin, float tmax);

/// The view ray through the centre of pixel (i, j): column \p i (0 at the
/// left), row \p j (0 at the **top**).
///
/// The pixel's centre on the film is (lecture 05, section 6)
///
///     p = e + F g + x r + y u,   with  x = ((i + 1/2) / W - 1/2) * w_film
///                                      y = (1/2 - (j + 1/2) / H) * h_film
///
/// where `F` is the focal length, `g` the forward vector (the gaze) and `u`
/// the up vector, `r = g x u` the image's right, `W x H` the image size in pixels,
/// `h_film` the film height and `w_film = h_film * W / H` its width.
///
/// \param camera the camera, as documented in Camera.
/// \param i      the pixel's column, 0 at the left.
/// \param j      the pixel's row, 0 at the top.
/// \return a ray with origin `camera.eye` and a direction pointing from the
///         eye through that point: `p - e` or any
///         positive multiple of it (normalised or not; the tests compare
///         directions, not lengths). Pixels outside the image are not an
///         error: they give rays beyond the film's edge.
Ray view_ray(const Camera& camera, int i, int j);

/// The colour of a pixel whose view ray hits nothing: black.
inline constexpr Color background{0.0f, 0.0f, 0.0f};

/// The flat-colour picture of \p scene seen by \p camera.
///
/// For every pixel (i, j) of the `camera.width` x `camera.height` image:
/// take view_ray(camera, i, j), find its closest hit with
/// find_intersection() in the window `[0, inf]` (everything in front
/// of the eye), and paint the pixel with the colour of the object hit, or
/// with #background when nothing is hit.
///
/// \param scene  what to draw.
/// \param camera where it is seen from, and the image size.
/// \return a Canvas of `camera.width` x `camera.height` pixels.
Canvas render(const Scene& scene, const Camera& camera);

}  // namespace raykit
