// Reference solution for step 03: the unit-direction shortcut and its
// geometric reading. Lecture: lectures/03-unit-direction.md
//
// Both functions compute the same numbers; they differ in what the names
// mean. Both take the precautions of sections 5 and 6 of the lecture.

#include "raykit/unit_direction.hpp"

#include <cmath>
#include <utility>

#include <glm/geometric.hpp>

namespace raykit {

namespace {

bool is_sphere(const Sphere& sphere) {
    return sphere.radius > 0.0f && std::isfinite(sphere.radius);
}

Roots sorted_pair(float t0, float t1) {
    // Inputs near float's limits can end in NaN; no root is ever NaN.
    if (std::isnan(t0) || std::isnan(t1)) return {};
    if (t0 > t1) std::swap(t0, t1);
    return {2, {t0, t1}};
}

}  // namespace

Roots sphere_roots_unit_dir(const Ray& ray, const Sphere& sphere) {
    if (!is_sphere(sphere)) return {};
    const glm::vec3 f = ray.origin - sphere.center;
    const glm::vec3 d = ray.direction;  // |d| = 1: a = d.d is 1 and drops out
    const float r = sphere.radius;

    // t^2 + 2 h t + c = 0, roots -h -+ sqrt(h^2 - c).
    const float h = glm::dot(f, d);
    const float c = glm::dot(f, f) - r * r;

    // h^2 - c = r^2 - |f - h d|^2: the same number without the cancellation
    // of two large squares (lecture section 5).
    const glm::vec3 l = f - h * d;
    const float disc = r * r - glm::dot(l, l);
    if (!(disc >= 0.0f)) return {};
    if (disc == 0.0f) return {1, {-h, -h}};

    // The root whose two terms share a sign, then the other from t0 t1 = c
    // (lecture section 6).
    const float q = -(h + std::copysign(std::sqrt(disc), h));
    return sorted_pair(q, c / q);
}

Roots sphere_roots_geometric(const Ray& ray, const Sphere& sphere) {
    if (!is_sphere(sphere)) return {};
    const glm::vec3 L = sphere.center - ray.origin;  // from the origin to the centre
    const glm::vec3 d = ray.direction;               // |d| = 1
    const float r = sphere.radius;

    // t_m: how far along the ray the centre projects; the closest approach.
    const float tm = glm::dot(L, d);

    // l_m^2, the squared distance from the centre to the line. Pythagoras
    // gives |L|^2 - t_m^2; measuring the leg itself, L - t_m d, gives the same
    // length without subtracting two large squares (lecture section 5).
    const glm::vec3 leg = L - tm * d;
    const float lm2 = glm::dot(leg, leg);

    // Pythagoras again, in the triangle centre - closest point - hit point.
    const float dt2 = r * r - lm2;
    if (!(dt2 >= 0.0f)) return {};
    if (dt2 == 0.0f) return {1, {tm, tm}};
    const float dt = std::sqrt(dt2);

    // The roots are t_m - dt and t_m + dt. Of the two, the one that adds
    // terms of the same sign (the root larger in magnitude) cannot cancel;
    // the other is (|L|^2 - r^2) / t_big, since the roots multiply to
    // |L|^2 - r^2 (lecture section 6).
    const float t_big = tm + std::copysign(dt, tm);
    const float t_small = (glm::dot(L, L) - r * r) / t_big;
    return sorted_pair(t_small, t_big);
}

}  // namespace raykit
