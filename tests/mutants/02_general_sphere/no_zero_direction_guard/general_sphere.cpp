// Mutant no_zero_direction_guard: a zero direction is not rejected: 0 / 0
// A complete step-02 answer with one realistic mistake. ./kit test grades it like a
// student's work and fails unless the basic tier catches it.

#include "raykit/general_sphere.hpp"

#include <cmath>

#include <glm/geometric.hpp>

namespace raykit {

Roots sphere_roots(const Ray& ray, const Sphere& sphere) {
    if (!(sphere.radius > 0.0f) || std::isinf(sphere.radius)) return {};
    const glm::vec3 oc = ray.origin - sphere.center;
    const float a = glm::dot(ray.direction, ray.direction);
    const float b = 2.0f * glm::dot(oc, ray.direction);
    const float c = glm::dot(oc, oc) - sphere.radius * sphere.radius;
    const float disc = b * b - 4.0f * a * c;
    if (disc < 0.0f) return {};
    if (disc == 0.0f) return {1, {-b / (2.0f * a), -b / (2.0f * a)}};
    const float s = std::sqrt(disc);
    return {2, {(-b - s) / (2.0f * a), (-b + s) / (2.0f * a)}};
}

std::optional<float> intersect_sphere(const Ray& ray, const Sphere& sphere, float tmin, float tmax) {
    const Roots r = sphere_roots(ray, sphere);
    for (int i = 0; i < r.count; ++i)
        if (tmin <= r.t[i] && r.t[i] <= tmax) return r.t[i];
    return std::nullopt;
}

}  // namespace raykit
