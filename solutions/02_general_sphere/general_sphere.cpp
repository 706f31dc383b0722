// Reference solution for step 02: a sphere anywhere, of any size.
// Lecture: lectures/02-general-sphere.md; why it is written this way:
// lectures/03-unit-direction.md, sections 5 to 7, and the benchmark's
// reading, docs/bench.md.

#include "raykit/general_sphere.hpp"

#include <cmath>
#include <limits>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace raykit {

namespace {

// A radius that is zero, negative, NaN or infinite describes no sphere.
bool is_sphere(const Sphere& sphere) {
    return sphere.radius > 0.0f && std::isfinite(sphere.radius);
}

}  // namespace

Roots sphere_roots(const Ray& ray, const Sphere& sphere) {
    if (!is_sphere(sphere)) return {};

    // Work in double. Every input is a float, so each product of two of them is
    // exact in double (24 + 24 significant bits fit in 53), and so is o - c
    // unless the origin and the centre differ in scale by more than about 2^29;
    // what rounds is only the sums.
    const glm::dvec3 f = glm::dvec3(ray.origin) - glm::dvec3(sphere.center);
    const glm::dvec3 d(ray.direction);
    const double r = sphere.radius;

    // a t^2 + 2 h t + c = 0, with the "half b" h. A zero or NaN direction
    // describes no line. (Squares of floats cannot overflow a double.)
    const double a = glm::dot(d, d);
    if (!(a > 0.0 && a < std::numeric_limits<double>::infinity())) return {};
    const double h = glm::dot(f, d);

    // The discriminant by Lagrange's identity, h^2 - a c = a r^2 - |f x d|^2:
    // |f x d| / |d| is how far the line passes from the centre (lecture 03's
    // geometric reading), so the discriminant is a (r^2 - distance^2) and
    // cancels only near a tangent. Each component of f x d is a difference of
    // two exact products, rounded once. Written as h^2 - a c instead, the two
    // terms are about |f|^2 |d|^2 each and their difference loses
    // log2(|f|^2 / r^2) bits: with |f| / r beyond about 1e5 (pbrt's own test
    // ranges reach 1e12) even double misclassifies rays. The benchmark
    // (docs/bench.md) measured this form at half an ulp on every family, for
    // 0.1 to 1 ns per ray (a few percent) more than h^2 - a c.
    const glm::dvec3 g = glm::cross(f, d);
    const double disc = a * (r * r) - glm::dot(g, g);

    // "!(disc >= 0)" is also true for NaN (a NaN or infinite input): a miss.
    if (!(disc >= 0.0)) return {};
    if (disc == 0.0) {
        const float t = static_cast<float>(-h / a);
        return {1, {t, t}};
    }

    // (-h -+ sqrt(disc)) / a. In float, one of these two sums cancels for a
    // tiny root beside a large one, and lecture 03 replaces it by the root
    // pair q / a, c / q. In double the cancellation costs at most about 1e-16
    // of |h| / a, far below a float ulp of any root except one about 1e-8
    // times smaller than the other; the benchmark measured the pair at 15% more time for
    // no gain on its families, so the plain form is kept. With a > 0 the root
    // with -sqrt is the smaller: the roots come out sorted.
    const double s = std::sqrt(disc);
    const float t0 = static_cast<float>((-h - s) / a);
    const float t1 = static_cast<float>((-h + s) / a);
    // An infinite input can still end in NaN; the contract says no root is NaN.
    if (std::isnan(t0) || std::isnan(t1)) return {};
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
