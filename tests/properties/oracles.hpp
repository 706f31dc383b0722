// Oracles: what must hold for any input, checked on the reference solutions by the
// property tests (seeded random inputs) and the fuzz targets (libFuzzer inputs).
//
// Each oracle returns an empty string when the property holds, otherwise a sentence
// saying what broke. The geometric truth (hit or miss) is computed in long double from
// the same float inputs, away from a near-tangent band where float cannot decide.
#pragma once

#include <cmath>
#include <optional>
#include <string>

#include <glm/geometric.hpp>

#include "raykit/ray.hpp"
#include "raykit/roots.hpp"

namespace raykit::oracles {

/// Relative width of the near-tangent band: a line whose distance from the centre is within
/// this fraction of the radius may be reported as a hit or a miss.
constexpr long double kTangentBand = 1e-3L;

inline bool finite(const glm::vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

/// Squared distance from `center` to the line of the ray, relative to radius^2, in long double.
inline long double line_distance2_over_r2(const Ray& ray, const glm::vec3& center, float radius) {
    const long double fx = (long double)ray.origin.x - center.x, fy = (long double)ray.origin.y - center.y,
                      fz = (long double)ray.origin.z - center.z;
    const long double dx = ray.direction.x, dy = ray.direction.y, dz = ray.direction.z;
    const long double a = dx * dx + dy * dy + dz * dz;
    const long double s = (fx * dx + fy * dy + fz * dz) / a;
    const long double px = fx - s * dx, py = fy - s * dy, pz = fz - s * dz;
    return (px * px + py * py + pz * pz) / ((long double)radius * radius);
}

/// The contract of Roots: count 0..2, sorted, tangent repeated, nothing NaN.
inline std::string roots_well_formed(const Roots& r) {
    if (r.count < 0 || r.count > 2) return "count is not 0, 1 or 2";
    for (int i = 0; i < r.count; ++i)
        if (std::isnan(r.t[i])) return "a root is NaN";
    if (r.count == 2 && !(r.t[0] <= r.t[1])) return "roots are not sorted";
    if (r.count == 1 && !(r.t[0] == r.t[1])) return "a tangent does not repeat its root";
    return {};
}

/// Hit or miss agrees with the long-double geometry outside the near-tangent band.
inline std::string roots_classified(const Ray& ray, const glm::vec3& center, float radius, const Roots& r) {
    const long double q = line_distance2_over_r2(ray, center, radius);
    if (!std::isfinite((double)q)) return {};
    // The band widens with the origin's distance in radii: a float reference forms the closest
    // point from coordinates of that size, each rounded by 2^-24 of it, so 1e5 radii away the line's
    // distance is known to about 1 % of the radius (the fuzzer found a 0.4 % miss there called a hit).
    const long double far = std::sqrt((long double)glm::dot(ray.origin - center, ray.origin - center)) / radius;
    const long double band = kTangentBand + 8 * far * 0x1p-24L;
    if (q > (1 + band) * (1 + band) && r.count != 0) return "a ray that provably misses was reported as a hit";
    if (band < 1 && q < (1 - band) * (1 - band) && r.count != 2) return "a ray that provably passes through was reported with fewer than two roots";
    return {};
}

/// A root lies on the sphere: | |o + t d - c| - r | is small against the sizes involved.
inline std::string root_on_surface(const Ray& ray, const glm::vec3& center, float radius, float t) {
    const long double px = ray.origin.x + (long double)t * ray.direction.x - center.x;
    const long double py = ray.origin.y + (long double)t * ray.direction.y - center.y;
    const long double pz = ray.origin.z + (long double)t * ray.direction.z - center.z;
    const long double dist = std::sqrt(px * px + py * py + pz * pz);
    // Float inputs carry relative error 2^-24 in every term; allow a few dozen of those over
    // the largest magnitude met on the way: |o - c|, |t d| and r.
    const long double scale = glm::length(ray.origin - center) + std::fabs(t) * glm::length(ray.direction) + radius;
    const long double bound = 64 * 5.96e-8L * scale;
    if (std::fabs(dist - radius) > bound) return "the point at a returned root is not on the sphere";
    return {};
}

/// A windowed answer lies in the closed window and is a root.
inline std::string hit_in_window(const Roots& r, float tmin, float tmax, const std::optional<float>& hit) {
    std::optional<float> expected;
    for (int i = 0; i < r.count && !expected; ++i)
        if (tmin <= r.t[i] && r.t[i] <= tmax) expected = r.t[i];
    if (hit && !(tmin <= *hit && *hit <= tmax)) return "a hit outside the window";
    if (hit && std::isnan(*hit)) return "a NaN hit";
    if (hit.has_value() != expected.has_value() || (hit && *hit != *expected))
        return "the windowed hit is not the smallest root inside the window";
    return {};
}

}  // namespace raykit::oracles
