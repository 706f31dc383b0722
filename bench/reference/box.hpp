// The empty Cornell box as a small table of axis-aligned rectangles, and the
// benchmark's own brute-force intersection with it.
//
// The table is the benchmark's, so the comparison with Embree works whether or
// not the kit's steps 04 and 05 are there. Its layout matches step 04's Rect:
// the plane `axis = offset` and, on the two other axes in increasing order
// (x then y, x then z, or y then z), the closed ranges [lo, hi].
#pragma once

#include <cmath>
#include <limits>

#include "vec.hpp"

namespace raykit::bench {

struct Rect3 {
    int axis;        ///< 0, 1 or 2: the rectangle lies in the plane x_axis = offset
    float offset;
    float lo[2];     ///< lower corner on the other two axes, in increasing order
    float hi[2];     ///< upper corner
};

/// The two axes other than `axis`, in increasing order.
inline void other_axes(int axis, int& u, int& v) {
    u = axis == 0 ? 1 : 0;
    v = axis == 2 ? 1 : 2;
}

template <class T> T component(const Vec3<T>& p, int i) { return i == 0 ? p.x : (i == 1 ? p.y : p.z); }

/// The Cornell box of Goral et al. (1984) in the dimensions of P. Shirley's
/// "Ray Tracing: The Next Week" (2016): a 555-unit cube open at z = 0, with
/// the ceiling light as a sixth rectangle just below the ceiling.
constexpr int kBoxRects = 6;
extern const Rect3 kCornellBox[kBoxRects];

/// One hit of the brute-force loop: which rectangle, and where.
struct BoxHit {
    bool hit = false;
    int rect = -1;
    float t = 0;
};

/// The ray o + t d against one rectangle in the closed window [tmin, tmax]:
/// t = (offset - o_axis) / d_axis, then the hit point's other two coordinates
/// must fall inside the rectangle. A ray parallel to the plane (d_axis = 0)
/// gives t = +-inf or NaN, which fails the window test.
/// Always inlined: whether GCC inlines it otherwise depends on how many callers it has, and the
/// loop below is timed as the benchmark's model of a renderer's inner loop.
template <class T>
__attribute__((always_inline)) inline bool hit_rect(const Vec3<T>& o, const Vec3<T>& d, const Rect3& r, T tmin,
                                                    T tmax, T& t) {
    int u, v;
    other_axes(r.axis, u, v);
    const T t_plane = (T(r.offset) - component(o, r.axis)) / component(d, r.axis);
    if (!(tmin <= t_plane && t_plane <= tmax)) return false;
    const T pu = component(o, u) + t_plane * component(d, u);
    const T pv = component(o, v) + t_plane * component(d, v);
    if (!(T(r.lo[0]) <= pu && pu <= T(r.hi[0]) && T(r.lo[1]) <= pv && pv <= T(r.hi[1]))) return false;
    t = t_plane;
    return true;
}

/// The closest hit over every rectangle: each one that is hit shrinks the
/// window. The window stays closed, so a rectangle at exactly the same t is
/// still found, and the strict test keeps the one listed first: the tie rule
/// of step 05's find_intersection (the Cornell box's light is coplanar with
/// its ceiling).
template <class T>
BoxHit brute_force(const Vec3<T>& o, const Vec3<T>& d, const Rect3* rects, int n, T tmin) {
    BoxHit best;
    T tmax = std::numeric_limits<float>::infinity();
    for (int i = 0; i < n; ++i) {
        T t;
        if (hit_rect(o, d, rects[i], tmin, tmax, t) && (!best.hit || t < tmax)) {
            tmax = t;
            best = {true, i, static_cast<float>(value(t))};
        }
    }
    return best;
}

}  // namespace raykit::bench
