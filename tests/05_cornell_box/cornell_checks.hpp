// Helpers shared by the step 05 suites: how scenes, hits and cameras are
// printed in a failure message, and the suites' own closest-hit oracle.
#pragma once

#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <optional>
#include <string>

#include "../support/grading.hpp"
#include "raykit/camera.hpp"
#include "raykit/scene.hpp"

namespace raykit::grading {

inline std::string show(const Rect& r) {
    return "Rect{axis " + std::to_string(r.axis) + ", offset " + show(r.offset) + ", lo " + show(r.lo) +
           ", hi " + show(r.hi) + "}";
}

inline std::string show(const std::optional<Hit>& hit) {
    if (!hit) return "no hit (std::nullopt)";
    return "Hit{t = " + show(hit->t) + ", index = " + std::to_string(hit->index) + "}";
}

inline std::string show(const Camera& c) {
    return "Camera{eye " + show(c.eye) + ", forward " + show(c.forward) + ", up " + show(c.up) +
           ", focal_length " + show(c.focal_length) + ", film_height " + show(c.film_height) + ", " +
           std::to_string(c.width) + " x " + std::to_string(c.height) + " pixels}";
}

inline std::string show(const Scene& scene) {
    std::string s;
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
        s += "\n              [" + std::to_string(i) + "] \"" + scene.objects[i].name + "\" " +
             show(scene.objects[i].shape);
    }
    return s.empty() ? " (empty)" : ":" + s;
}

/// Colours are typed in from a table: equal to two decimals.
inline bool same_color(const Color& expected, const Color& got) {
    for (int k = 0; k < 3; ++k) {
        if (!(std::fabs(expected[k] - got[k]) <= 0.005f)) return false;
    }
    return true;
}

/// The object a ray sees first, found by the suite itself with the student's
/// intersect_rect (step 04, done): ties go to the object listed first. The
/// model's cases use it so that they do not depend on find_intersection.
inline const Object* first_seen(const Scene& scene, const Ray& ray) {
    const Object* best = nullptr;
    float best_t = std::numeric_limits<float>::infinity();
    for (const Object& object : scene.objects) {
        const std::optional<float> t = intersect_rect(ray, object.shape, 0.0f, best_t);
        if (t && (best == nullptr || *t < best_t)) {
            best = &object;
            best_t = *t;
        }
    }
    return best;
}

}  // namespace raykit::grading
