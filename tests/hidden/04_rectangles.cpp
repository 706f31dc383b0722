// Hidden cases of step 04 (see hidden.hpp): axis-aligned rectangles, every axis.

#include "hidden.hpp"
#include "raykit/rect.hpp"
#include "edge_causes.hpp"
#include "rules.hpp"

using namespace raykit;
using namespace raykit::hidden;

namespace {

using raykit::grading::inf;

struct Input {
    Ray ray;
    Rect rect;
    float tmin, tmax;
};

std::string shown(const Input& in) {
    const Rect& r = in.rect;
    return grading::show(in.ray) + "; rect axis " + std::to_string(r.axis) + ", offset " + grading::show(r.offset) +
           ", lo " + grading::show(r.lo) + ", hi " + grading::show(r.hi) + "; window [" + grading::show(in.tmin) +
           ", " + grading::show(in.tmax) + "]";
}

// The 3D point with coordinate `offset` on `axis` and in-plane coordinates uv
// (the two other axes in increasing order).
glm::vec3 on_plane(int axis, float offset, glm::vec2 uv) {
    glm::vec3 p;
    p[axis] = offset;
    p[axis == 0 ? 1 : 0] = uv.x;
    p[axis == 2 ? 1 : 2] = uv.y;
    return p;
}

Rect random_rect(Draw& d) {
    Rect r{};
    r.axis = d.integer(0, 2);
    r.offset = d.uniform(-20, 20);
    r.lo = {d.uniform(-20, 10), d.uniform(-20, 10)};
    r.hi = r.lo + glm::vec2{d.uniform(0.5f, 10), d.uniform(0.5f, 10)};
    return r;
}

// In-plane point: inside by a margin (fraction of the size), or outside by one.
glm::vec2 inside(Draw& d, const Rect& r) {
    const glm::vec2 f{d.uniform(0.1f, 0.9f), d.uniform(0.1f, 0.9f)};
    return r.lo + f * (r.hi - r.lo);
}
glm::vec2 outside(Draw& d, const Rect& r) {
    glm::vec2 p = inside(d, r);
    const int k = d.integer(0, 1);
    const float size = r.hi[k] - r.lo[k];
    p[k] = d.coin() ? r.hi[k] + d.uniform(0.1f, 1) * size : r.lo[k] - d.uniform(0.1f, 1) * size;
    return p;
}

Ray towards(Draw& d, const Rect& r, glm::vec2 uv) {
    const glm::vec3 target = on_plane(r.axis, r.offset, uv);
    glm::vec3 o = target + d.uniform(1, 30) * d.direction();
    if (std::fabs(o[r.axis] - r.offset) < 0.5f) o[r.axis] = r.offset + d.sign() * d.uniform(0.5f, 5);
    return aimed(o, target, d.uniform(0.1f, 8));
}

template <class Make>
void family(const char* family, Make make, const char* why) {
    Draw draw(family);
    for (int i = 0; i < draws; ++i) {
        const Input in = make(draw);
        const auto expected = remote::reference<std::optional<float>>("intersect_rect", in.ray, in.rect, in.tmin, in.tmax);
        const auto got = intersect_rect(in.ray, in.rect, in.tmin, in.tmax);
        if (!agree(expected, got)) {
            // A hit exactly on an end of the window that the code's own t, within the basic tolerance,
            // puts an ulp outside (3.0000002 for an exact 3, from a product with an inexact reciprocal):
            // skipping it is right for the t it has, as the visible case "a hit exactly at tmax along a
            // direction whose reciprocal is no float" accepts (check_hit_at_end). Asked with the window
            // widened by the tolerance; an open window still fails, its t being the exact one.
            if (expected && !got && (*expected == in.tmin || *expected == in.tmax)) {
                const auto widened = intersect_rect(in.ray, in.rect, in.tmin - grading::tolerance_at(in.tmin),
                                                    in.tmax + grading::tolerance_at(in.tmax));
                if (widened && grading::close(*expected, *widened) && (*widened < in.tmin || *widened > in.tmax))
                    continue;
                (void)intersect_rect(in.ray, in.rect, in.tmin, in.tmax);    // the call the picture records
            }
            // A missed hit on an edge: the edges left out, or the point's coordinates off (edge_causes.hpp).
            const grading::EdgeCause cause = grading::edge_cause(
                [](const Ray& ray, const Rect& rect, float tmin, float tmax) { return intersect_rect(ray, rect, tmin, tmax); },
                in.ray, in.rect, in.tmin, in.tmax, expected, got);
            // Closed comparisons, and a point computed an ulp or so outside an exact edge: right within
            // rounding, like a root a few ulps past a window end, so both sides are accepted. Which draws
            // put a point on an edge must not decide the verdict (issue 45: an object-space transform
            // failed 8 of 10 identities). Leaving the edges out is still caught, on every draw.
            if (cause.rounding) continue;
            // No probe of an own epsilon here (grading.hpp, own_epsilon): its rays are fixed, so a hidden
            // case that made those calls would show a submission inputs a visible case shows too, which the
            // integrity self-tests count as hidden inputs carried over. The visible cases name it.
            if (cause.matched) (void)intersect_rect(in.ray, in.rect, in.tmin, in.tmax);   // the call the picture records
            grading::check_hit("intersect_rect(ray, rect, tmin, tmax)", input_note(i, shown(in)), expected, got,
                               cause.matched ? cause.text : why);
            return;
        }
    }
}

// Integer geometry on a random axis: an axis-aligned ray of power-of-two length,
// its in-plane point given exactly; t is exact.
Input exact(Draw& d, glm::vec2 uv, const Rect& r) {
    const float s = d.sign();
    const float k = static_cast<float>(d.integer(1, 12));
    glm::vec3 o = on_plane(r.axis, r.offset - s * k, uv);
    glm::vec3 dir{0, 0, 0};
    dir[r.axis] = s * d.power_of_two(-2, 2);
    return {{o, dir}, r, 0, inf};
}

Rect integer_rect(Draw& d) {
    Rect r{};
    r.axis = d.integer(0, 2);
    r.offset = static_cast<float>(d.integer(-10, 10));
    r.lo = {static_cast<float>(d.integer(-10, 0)), static_cast<float>(d.integer(-10, 0))};
    r.hi = r.lo + glm::vec2{static_cast<float>(d.integer(1, 8)), static_cast<float>(d.integer(1, 8))};
    return r;
}

}  // namespace

TEST_SUITE_BEGIN("hidden");

TEST_CASE("intersect_rect on random rectangles of every axis hit inside" *
          doctest::description("4. Inside the rectangle")) {
    family("04 inside", [](Draw& d) {
        const Rect r = random_rect(d);
        return Input{towards(d, r, inside(d, r)), r, 0, inf};
    }, "The ray meets the plane inside the rectangle: a hit at that t.");
}

TEST_CASE("intersect_rect on random rectangles of every axis missed outside" *
          doctest::description("4. Inside the rectangle")) {
    family("04 outside", [](Draw& d) {
        const Rect r = random_rect(d);
        return Input{towards(d, r, outside(d, r)), r, 0, inf};
    }, "The ray meets the plane outside the rectangle: no hit.");
}

TEST_CASE("intersect_rect on exact edges and corners of every axis" * doctest::description("4. Inside the rectangle")) {
    family("04 edges", [](Draw& d) {
        const Rect r = integer_rect(d);
        glm::vec2 uv = inside(d, r);
        const int k = d.integer(0, 2);  // 0: u on an edge, 1: v on an edge, 2: a corner
        if (k != 1) uv.x = d.coin() ? r.lo.x : r.hi.x;
        if (k != 0) uv.y = d.coin() ? r.lo.y : r.hi.y;
        if (d.integer(0, 3) == 0) uv[d.integer(0, 1)] += d.sign() * 0.5f * (r.hi.x - r.lo.x + 1);  // just off
        return exact(d, uv, r);
    }, "The rectangle is closed: a hit exactly on an edge or a corner counts.");
}

TEST_CASE("intersect_rect on rays parallel to the plane" * doctest::description("3. Rays parallel to the plane")) {
    family("04 parallel", [](Draw& d) {
        const Rect r = random_rect(d);
        glm::vec3 o = on_plane(r.axis, r.offset + d.sign() * d.uniform(0.5f, 5), inside(d, r));
        glm::vec3 dir = d.direction();
        dir[r.axis] = 0;
        if (glm::dot(dir, dir) == 0) dir[(r.axis + 1) % 3] = 1;
        return Input{{o, dir}, r, 0, inf};
    }, "A ray parallel to the plane never meets it.");
}

TEST_CASE("intersect_rect with windows behind and exact window ends" *
          doctest::description("5. The window and both sides")) {
    family("04 window", [](Draw& d) {
        const Rect r = integer_rect(d);
        Input in = exact(d, inside(d, r), r);
        const float t = remote::reference<std::optional<float>>("intersect_rect", in.ray, r, -inf, inf).value_or(0);
        switch (d.integer(0, 3)) {
            case 0: in.tmin = t, in.tmax = t + d.uniform(0, 3); break;
            case 1: in.tmin = t - d.uniform(0, 3), in.tmax = t; break;
            case 2: in.tmin = t + d.uniform(0.5f, 3), in.tmax = inf; break;    // the hit is before the window
            default: in.ray.direction = -in.ray.direction, in.tmin = 0;        // the rectangle is behind
        }
        return in;
    }, "The window is closed at both ends; a rectangle behind the origin is not hit.");
}

TEST_SUITE_END();
