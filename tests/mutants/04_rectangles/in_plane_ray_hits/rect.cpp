// Mutant in_plane_ray_hits: a ray lying in the plane is taken to hit where it starts
// A complete step-04 answer with one realistic mistake. ./kit test grades it like a
// student's work and fails unless the basic tier catches it.

#include "raykit/rect.hpp"

#include <cmath>

namespace raykit {

std::optional<float> intersect_rect(const Ray& ray, const Rect& rect, float tmin, float tmax) {
    if (rect.axis < 0 || rect.axis > 2) return std::nullopt;
    const int k = rect.axis;
    const int u = k == 0 ? 1 : 0;
    const int v = k == 2 ? 1 : 2;
    if (ray.direction[k] == 0.0f) {
        // In the plane: "it touches the rectangle right away" (it does not: it sees it edge-on).
        const bool in_plane = ray.origin[k] == rect.offset;
        const bool inside = rect.lo.x <= ray.origin[u] && ray.origin[u] <= rect.hi.x &&
                            rect.lo.y <= ray.origin[v] && ray.origin[v] <= rect.hi.y;
        if (in_plane && inside && tmin <= 0.0f && 0.0f <= tmax) return 0.0f;
        return std::nullopt;
    }
    const float t = (rect.offset - ray.origin[k]) / ray.direction[k];
    if (!(tmin <= t && t <= tmax)) return std::nullopt;
    const float pu = ray.origin[u] + t * ray.direction[u];
    const float pv = ray.origin[v] + t * ray.direction[v];
    if (!(rect.lo.x <= pu && pu <= rect.hi.x && rect.lo.y <= pv && pv <= rect.hi.y)) return std::nullopt;
    return t;
}

}  // namespace raykit
