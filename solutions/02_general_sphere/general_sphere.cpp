// Reference solution for step 02: a sphere anywhere, of any size.
// Lecture: lectures/02-general-sphere.md; why it is written this way:
// lectures/03-unit-direction.md, sections 5 to 7.

#include "raykit/general_sphere.hpp"

#include <cmath>
#include <limits>
#include <utility>

#include <glm/geometric.hpp>

namespace raykit {

namespace {

// A radius that is zero, negative, NaN or infinite describes no sphere.
bool is_sphere(const Sphere& sphere) {
    return sphere.radius > 0.0f && std::isfinite(sphere.radius);
}

}  // namespace

Roots sphere_roots(const Ray& ray, const Sphere& sphere) {
    if (!is_sphere(sphere)) return {};

    // Work from the centre: f is the origin seen from the centre, so the
    // sphere becomes |f + t d|^2 = r^2. Subtracting first keeps the numbers
    // small when both the ray and the sphere are far from the world origin.
    const glm::vec3 f = ray.origin - sphere.center;
    const glm::vec3 d = ray.direction;
    const float r = sphere.radius;

    // a t^2 + 2 h t + c = 0, with the "half b" h.
    // A zero or NaN direction describes no line. A direction so long that d.d
    // overflows cannot be handled in float either (inf / inf is NaN): no line.
    const float a = glm::dot(d, d);
    if (!(a > 0.0f && a <= std::numeric_limits<float>::max())) return {};
    const float h = glm::dot(f, d);
    const float c = glm::dot(f, f) - r * r;

    // The quarter discriminant h^2 - a c equals a (r^2 - |l|^2), where
    // l = f - (h/a) d runs from the centre to the line's closest point. h^2
    // and a c are both about |f|^2 |d|^2 and cancel when the sphere is far
    // away or small; l is short in exactly those cases, and the error in h
    // enters |l|^2 only squared, because it moves l along d, at right angles
    // to l itself (Haines et al., Ray Tracing Gems, chapter 7, 2019).
    const glm::vec3 l = f - (h / a) * d;
    const float disc = a * (r * r - glm::dot(l, l));

    // "!(disc >= 0)" is also true for NaN (a NaN or infinite input): a miss.
    if (!(disc >= 0.0f)) return {};
    if (disc == 0.0f) {
        const float t = -h / a;
        return {1, {t, t}};
    }

    // (-h -+ sqrt(disc)) / a: one of the two sums adds numbers of the same
    // sign and never cancels; it gives q and the root q / a. The other root
    // comes from the product of the roots, t0 t1 = c / a, as c / q.
    const float q = -(h + std::copysign(std::sqrt(disc), h));
    float t0 = q / a;
    float t1 = c / q;
    // Inputs near float's limits (an origin whose f.f overflows) can still end
    // in NaN; the contract says no root is ever NaN.
    if (std::isnan(t0) || std::isnan(t1)) return {};
    if (t0 > t1) std::swap(t0, t1);
    return {2, {t0, t1}};
}

std::optional<float> intersect_sphere(const Ray& ray, const Sphere& sphere, float tmin, float tmax) {
    const Roots roots = sphere_roots(ray, sphere);
    // Roots are sorted, so the first one inside the window is the closest.
    for (int i = 0; i < roots.count; ++i) {
        const float t = roots.t[i];
        if (tmin <= t && t <= tmax) return t;
    }
    return std::nullopt;
}

}  // namespace raykit
