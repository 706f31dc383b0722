// Derived from the reference solution for step 05: closest hit, view rays and the render loop.
// Lecture: lectures/05-cornell-box.md, sections 4 to 7.

#include "raykit/render.hpp"

#include <limits>

#include <glm/geometric.hpp>

namespace raykit {

std::optional<Hit> find_intersection(const Ray& ray, const Scene& scene, float tmin, float tmax) {
    std::optional<Hit> best;
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
        // Shrinking the window to the best hit so far lets intersect_rect
        // reject farther objects itself. The window is closed, so an object
        // at exactly the same t is still reported: the strict test below
        // keeps the one listed first.
        const float limit = best ? best->t : tmax;
        const std::optional<float> t = intersect_rect(ray, scene.objects[i].shape, tmin, limit);
        if (t && (!best || *t < best->t)) best = Hit{*t, i};
    }
    return best;
}

Ray view_ray(const Camera& camera, int i, int j) {
    const glm::vec3 right = glm::cross(camera.forward, camera.up);
    const float film_width = camera.film_height * static_cast<float>(camera.width) / static_cast<float>(camera.height);
    // Pixel centres: (i + 1/2) / W runs from 1/(2W) to 1 - 1/(2W), so no ray
    // goes through the film's very edge and the image is symmetric.
    const float x = ((static_cast<float>(i) + 0.5f) / static_cast<float>(camera.width) - 0.5f) * film_width;
    // Rows count downwards: row 0 is the top of the image, +up on the film.
    const float y = (0.5f - (static_cast<float>(j) + 0.5f) / static_cast<float>(camera.height)) * camera.film_height;
    const glm::vec3 direction = camera.focal_length * camera.forward + x * right + y * camera.up;
    return Ray{camera.eye, direction};
}

Canvas render(const Scene& scene, const Camera& camera) {
    Canvas canvas(camera.width, camera.height);
    const float inf = std::numeric_limits<float>::infinity();
    for (int j = 0; j < camera.height; ++j) {
        for (int i = 0; i < camera.width; ++i) {
            const std::optional<Hit> hit = find_intersection(view_ray(camera, i, j), scene, 0.0f, inf);
            canvas.at(i, j) = hit ? scene.objects[hit->index].color : background;
        }
    }
    return canvas;
}

}  // namespace raykit
