// The rectangle oracle: where the ray meets the plane, in long double, and whether that point is
// inside, outside, or too close to an edge for float to decide.
#pragma once

#include <cmath>
#include <optional>
#include <string>

#include "raykit/rect.hpp"

namespace raykit::oracles {

enum class Truth { hit, miss, unsure };

/// What an exact computation says about ray and rect in the window [tmin, tmax].
inline Truth rect_truth(const Ray& ray, const Rect& rect, float tmin, float tmax) {
    if (rect.axis < 0 || rect.axis > 2) return Truth::miss;
    const int k = rect.axis, u = k == 0 ? 1 : 0, v = k == 2 ? 1 : 2;
    const long double dk = ray.direction[k];
    if (dk == 0) return Truth::miss;
    const long double t = ((long double)rect.offset - ray.origin[k]) / dk;
    const long double pu = ray.origin[u] + t * ray.direction[u];
    const long double pv = ray.origin[v] + t * ray.direction[v];
    // Margins, so that rounding cannot flip the answer: float rounds each term of a sum, so the error
    // scales with the terms, not with the result. o[u] + t d[u] near 0 from two large terms that cancel
    // is off by ulps of those terms, and an error in t moves the point by |d[u]| times that error.
    const long double eps = 1e-5L;  // about 170 float ulps
    const long double ok = ray.origin[k], off = rect.offset;
    const long double mt = eps * ((std::fabs(off) + std::fabs(ok)) / std::fabs(dk) + std::fabs(t) + 1);
    const long double du = ray.direction[u], dv = ray.direction[v];
    const long double mu = eps * (std::fabs((long double)ray.origin[u]) + std::fabs(t * du) + 1) + std::fabs(du) * mt;
    const long double mv = eps * (std::fabs((long double)ray.origin[v]) + std::fabs(t * dv) + 1) + std::fabs(dv) * mt;
    const bool in = tmin + mt <= t && t <= tmax - mt && rect.lo.x + mu <= pu && pu <= rect.hi.x - mu &&
                    rect.lo.y + mv <= pv && pv <= rect.hi.y - mv;
    const bool out = t < tmin - mt || t > tmax + mt || pu < rect.lo.x - mu || pu > rect.hi.x + mu ||
                     pv < rect.lo.y - mv || pv > rect.hi.y + mv;
    return in ? Truth::hit : out ? Truth::miss : Truth::unsure;
}

inline std::string rect_agrees(const Ray& ray, const Rect& rect, float tmin, float tmax,
                               const std::optional<float>& hit) {
    if (hit && std::isnan(*hit)) return "a NaN hit";
    if (hit && !(tmin <= *hit && *hit <= tmax)) return "a hit outside the window";
    switch (rect_truth(ray, rect, tmin, tmax)) {
        case Truth::hit:
            if (!hit) return "a ray that provably hits the rectangle was reported as a miss";
            break;
        case Truth::miss:
            if (hit) return "a ray that provably misses the rectangle was reported as a hit";
            break;
        case Truth::unsure: break;
    }
    return {};
}

}  // namespace raykit::oracles
