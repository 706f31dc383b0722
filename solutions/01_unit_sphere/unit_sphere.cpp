// Reference solution for step 01: the unit sphere at the origin.
// Lecture: lectures/01-unit-sphere.md

#include "raykit/unit_sphere.hpp"

#include <cmath>
#include <limits>
#include <utility>

#include <glm/geometric.hpp>

namespace raykit {

Roots unit_sphere_roots(const Ray& ray) {
    const glm::vec3 o = ray.origin;
    const glm::vec3 d = ray.direction;

    // |o + t d|^2 = 1 is a t^2 + 2 h t + c = 0 with the "half b" h = o.d.
    const float a = glm::dot(d, d);
    const float h = glm::dot(o, d);
    const float c = glm::dot(o, o) - 1.0f;

    // A zero or NaN direction describes no line: nothing to hit. A direction so long that
    // d.d overflows, or so short that it underflows to 0, cannot be followed in float (inf / inf
    // or 0 / 0 would make a root NaN): the header lets it count as a miss, which this float
    // reference does (the true roots, computed in double, would be right too). A short direction
    // whose d.d is still a normal float (1e-7, say) is an ordinary ray.
    if (!(a > 0.0f && a <= std::numeric_limits<float>::max())) return {};

    // The quarter discriminant h^2 - a c, written as a (1 - |o - (h/a) d|^2).
    // o - (h/a) d is the vector from the centre to the closest point of the
    // line, so the bracket is 1 minus the squared distance of the line from
    // the centre. Computing it this way avoids subtracting two nearly equal
    // large numbers (h^2 and a c) when the sphere is far away.
    const glm::vec3 closest = o - (h / a) * d;
    const float disc = a * (1.0f - glm::dot(closest, closest));

    // "!(disc >= 0)" is also true for NaN, which then reports a miss.
    if (!(disc >= 0.0f)) return {};

    if (disc == 0.0f) {
        const float t = -h / a;
        return {1, {t, t}};
    }

    // The two roots are (-h -+ sqrt(disc)) / a. Adding numbers of the same
    // sign never cancels, so compute q = -(h + sign(h) sqrt(disc)) and get
    // the other root from the product of the roots, t0 t1 = c / a.
    const float s = std::sqrt(disc);
    const float q = -(h + std::copysign(s, h));
    float t0 = q / a;
    float t1 = c / q;
    // Inputs near float's limits (an origin whose o.o overflows, say) can still end in NaN.
    if (std::isnan(t0) || std::isnan(t1)) return {};
    if (t0 > t1) std::swap(t0, t1);
    return {2, {t0, t1}};
}

std::optional<float> intersect_unit_sphere(const Ray& ray, float tmin, float tmax) {
    const Roots roots = unit_sphere_roots(ray);
    // Roots are sorted, so the first one inside the window is the closest.
    for (int i = 0; i < roots.count; ++i) {
        const float t = roots.t[i];
        if (tmin <= t && t <= tmax) return t;
    }
    return std::nullopt;
}

}  // namespace raykit
