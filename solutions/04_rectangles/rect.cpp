// Reference solution for step 04: axis-aligned rectangles.
// Lecture: lectures/04-rectangles.md

#include "raykit/rect.hpp"

namespace raykit {

namespace {

// The two coordinates of p that lie in a plane perpendicular to `axis`,
// in increasing axis order: (y, z), (x, z) or (x, y). Getting this order
// wrong swaps the rectangle's width and height, which a square rectangle
// would hide.
glm::vec2 in_plane(const glm::vec3& p, int axis) {
    if (axis == 0) return {p.y, p.z};
    if (axis == 1) return {p.x, p.z};
    return {p.x, p.y};
}

}  // namespace

std::optional<float> intersect_rect(const Ray& ray, const Rect& rect, float tmin, float tmax) {
    // Any other axis is no rectangle; checked first so that ray.direction[axis]
    // below never reads outside the vector.
    if (rect.axis < 0 || rect.axis > 2) return std::nullopt;

    // The plane x[axis] = offset is crossed where o[axis] + t d[axis] = offset.
    // A ray parallel to the plane (d[axis] == 0; -0.0 compares equal to 0)
    // never crosses it, or lies in it and grazes the rectangle edge-on; the
    // division would give +-inf or 0/0 = NaN, so stop here.
    const float d = ray.direction[rect.axis];
    if (d == 0.0f) return std::nullopt;
    const float t = (rect.offset - ray.origin[rect.axis]) / d;

    // Written as "not inside" so that a NaN t (from a NaN origin or offset)
    // is rejected too: every comparison with NaN is false.
    if (!(tmin <= t && t <= tmax)) return std::nullopt;

    // The hit point's in-plane coordinates; its coordinate along `axis` is
    // the offset by construction and is not needed.
    const glm::vec2 q = in_plane(point_at(ray, t), rect.axis);

    // Closed on every side: edges and corners belong to the rectangle. A NaN
    // coordinate fails every comparison and is a miss.
    const bool inside = rect.lo.x <= q.x && q.x <= rect.hi.x && rect.lo.y <= q.y && q.y <= rect.hi.y;
    if (!inside) return std::nullopt;
    return t;
}

}  // namespace raykit
