// Why a rectangle's hit on an edge was missed, measured on the student's function (used by the hidden
// cases, beside them: it leaves the handout with them).
//
// A hit exactly on an edge (or a corner) that comes back as a miss has two causes that read alike from
// the outside: the edges are left out (a strict comparison, u < hi), or the in-plane coordinates the
// function computes for the point are not the exact ones and land just outside (a transform into the
// rectangle's own space, a reciprocal of its size): the comparisons are right, the point is not. The
// kit tells them apart by asking the same function two more things: the same case with the rectangle
// a little larger (does it then take the hit? if not, neither cause explains the miss), and hits on the
// corners of the unit square [0, 1]^2 in the same plane, where any way of computing the coordinates is
// exact (does it count edges at all?). The first is a slip; the second is right within rounding, and the
// hidden family accepts it (`rounding`), as a root a few ulps past a window end is accepted.
#pragma once

#include <cmath>
#include <optional>
#include <string>

#include "../support/grading.hpp"
#include "raykit/rect.hpp"

namespace raykit::grading {

/// What edge_cause measured: `matched` when it found the cause, `text` the sentence that says so.
struct EdgeCause {
    bool matched = false;
    bool rounding = false;  ///< closed comparisons, the point an ulp or so outside: right within rounding
    std::string text;
};

/// The cause of a missed hit exactly on an edge of `rect` (expected `expected`, got no hit), measured by
/// calling `f(ray, rect, tmin, tmax)` again on a grown rectangle and on the unit square's corners.
/// Unmatched (empty) when the expected hit is not on an edge, the answer is not a miss, or neither
/// cause explains it. The caller calls the function under test once more afterwards, so that the call
/// the case's picture records is still the one checked.
template <class F>
EdgeCause edge_cause(F f, const Ray& ray, const Rect& rect, float tmin, float tmax,
                     const std::optional<float>& expected, const std::optional<float>& got) {
    if (!expected || got || rect.axis < 0 || rect.axis > 2) return {};
    const int u_axis = rect.axis == 0 ? 1 : 0, v_axis = rect.axis == 2 ? 1 : 2;
    // The exact hit point's in-plane coordinates (double holds a float product and sum exactly enough
    // to tell "exactly on the edge" for the kit's cases, whose points are exact in float).
    const double t = *expected;
    const double u = double(ray.origin[u_axis]) + t * double(ray.direction[u_axis]);
    const double v = double(ray.origin[v_axis]) + t * double(ray.direction[v_axis]);
    if (!(u == rect.lo.x || u == rect.hi.x || v == rect.lo.y || v == rect.hi.y)) return {};

    Rect grown = rect;
    const glm::vec2 margin{tolerance_at(rect.hi.x - rect.lo.x) + tolerance_at(std::fabs(rect.lo.x) + std::fabs(rect.hi.x)),
                           tolerance_at(rect.hi.y - rect.lo.y) + tolerance_at(std::fabs(rect.lo.y) + std::fabs(rect.hi.y))};
    grown.lo -= margin;
    grown.hi += margin;
    const std::optional<float> wider = f(ray, grown, tmin, tmax);
    if (!wider || !close(*expected, *wider)) return {};

    // The unit square in the same plane, each corner hit straight along the axis from one unit away.
    const Rect unit{rect.axis, 0.0f, {0.0f, 0.0f}, {1.0f, 1.0f}};
    for (const glm::vec2 corner : {glm::vec2{0, 0}, glm::vec2{1, 1}, glm::vec2{0, 1}, glm::vec2{1, 0}}) {
        glm::vec3 o(0.0f), d(0.0f);
        o[rect.axis] = -1.0f;
        o[u_axis] = corner.x;
        o[v_axis] = corner.y;
        d[rect.axis] = 1.0f;
        const std::optional<float> hit = f(Ray{o, d}, unit, 0.0f, inf);
        if (!hit || *hit != 1.0f)
            return {true, false, "Measured on your answer: it misses a hit exactly on a corner of the unit square "
                          "[0, 1] x [0, 1] too (ray from " + show(o) + " along the axis), and takes this one once the "
                          "rectangle is a little larger: it leaves the edges out, where the rectangle is closed "
                          "(lo <= u <= hi and lo <= v <= hi)."};
    }
    return {true, true, "Measured on your answer: it counts hits exactly on the edges of the unit square [0, 1] x [0, 1], "
                  "and takes this one once the rectangle is a little larger; so its comparisons are closed, and "
                  "what is off is the point: the exact hit lies on the edge, at (u, v) = (" + show(float(u)) + ", " +
                  show(float(v)) + "), and the in-plane coordinates your function computes for it land just "
                  "outside, by a rounding on the way (a transform into the rectangle's own space, a reciprocal of "
                  "its size). The task compares the hit point's own coordinates with lo and hi, which are exact "
                  "here."};
}

}  // namespace raykit::grading
