// Mutant geometric_radius_not_squared: the second Pythagoras uses r instead of r^2
// A complete step-03 answer with one realistic mistake. ./kit test grades it like a
// student's work and fails unless the basic tier catches it.

#include "raykit/unit_direction.hpp"

#include <cmath>

#include <glm/geometric.hpp>

namespace raykit {

Roots sphere_roots_unit_dir(const Ray& ray, const Sphere& sphere) {
    if (!(sphere.radius > 0.0f) || std::isinf(sphere.radius)) return {};
    const glm::vec3 f = ray.origin - sphere.center;
    const float h = glm::dot(f, ray.direction);
    const float c = glm::dot(f, f) - sphere.radius * sphere.radius;
    const float disc = h * h - c;
    if (disc < 0.0f) return {};
    if (disc == 0.0f) return {1, {-h, -h}};
    const float s = std::sqrt(disc);
    return {2, {-h - s, -h + s}};
}

Roots sphere_roots_geometric(const Ray& ray, const Sphere& sphere) {
    if (!(sphere.radius > 0.0f) || std::isinf(sphere.radius)) return {};
    const glm::vec3 L = sphere.center - ray.origin;
    const float tm = glm::dot(L, ray.direction);
    const float lm2 = glm::dot(L, L) - tm * tm;
    const float dt2 = sphere.radius - lm2;
    if (dt2 < 0.0f) return {};
    if (dt2 == 0.0f) return {1, {tm, tm}};
    const float dt = std::sqrt(dt2);
    return {2, {tm - dt, tm + dt}};
}

}  // namespace raykit
