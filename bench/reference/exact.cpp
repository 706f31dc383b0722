// The float128 yardstick. See exact.hpp.

#include "exact.hpp"

#include <cmath>
#include <initializer_list>
#include <limits>
#include <utility>

#include <quadmath.h>

namespace raykit::bench {

namespace {

Vec3<quad> widen(const Vec3<float>& v) { return {quad(v.x), quad(v.y), quad(v.z)}; }

quad abs_q(quad x) { return x < 0 ? -x : x; }

}  // namespace

ExactSphere exact_sphere(const Sample<float>& s, double band) {
    // Every input is a float, so f = o - c and the products below are exact
    // or nearly so in 113 bits; the roots come out with a relative error far
    // below a double's ulp.
    const Vec3<quad> f = widen(s.o) - widen(s.c);
    const Vec3<quad> d = widen(s.d);
    const quad r = s.r;
    const quad a = dot(d, d);
    const quad h = dot(f, d);
    const quad c = dot(f, f) - r * r;
    // Distance of the line from the centre: |f x d| / |d| (Lagrange's identity
    // keeps this free of the cancellation in |f|^2 - h^2/a).
    const Vec3<quad> fxd = cross(f, d);
    const quad dist2 = dot(fxd, fxd) / a;
    const quad disc = a * (r * r - dist2);

    ExactSphere e;
    e.impact = static_cast<double>(sqrtq(dist2) / r);
    e.near_tangent = std::fabs(e.impact - 1.0) <= band;
    if (disc < 0) return e;
    e.hit = true;
    const quad root = sqrtq(disc);
    const quad q = -(h + (h < 0 ? -root : root));
    quad t0 = q / a, t1 = c / q;
    if (q == 0) t0 = t1 = -h / a;  // only for h = 0 and a tangent
    if (t1 < t0) std::swap(t0, t1);
    e.t[0] = t0;
    e.t[1] = t1;
    return e;
}

bool first_hit(const ExactSphere& e, quad& t) {
    if (!e.hit) return false;
    for (const quad root : e.t) {
        if (root >= 0) {
            t = root;
            return true;
        }
    }
    return false;
}

ExactBoxHit exact_box(const Vec3<float>& o_in, const Vec3<float>& d_in, const Rect3* rects, int n,
                      float tmin) {
    const Vec3<quad> o = widen(o_in), d = widen(d_in);
    ExactBoxHit best;
    // First the closest hit, then whether the ray passes near an edge of any
    // rectangle whose plane it crosses before (or at) that hit.
    quad plane_t[kMaxRects];
    quad inside[kMaxRects];  // signed distance from the rectangle's boundary, positive inside
    bool crosses[kMaxRects];
    for (int i = 0; i < n && i < kMaxRects; ++i) {
        const Rect3& r = rects[i];
        int u, v;
        other_axes(r.axis, u, v);
        const quad dn = component(d, r.axis);
        crosses[i] = false;
        if (dn == 0) continue;
        const quad t = (quad(r.offset) - component(o, r.axis)) / dn;
        if (t < quad(tmin)) continue;
        const quad pu = component(o, u) + t * component(d, u);
        const quad pv = component(o, v) + t * component(d, v);
        quad m = pu - quad(r.lo[0]);
        for (const quad side : {quad(r.hi[0]) - pu, pv - quad(r.lo[1]), quad(r.hi[1]) - pv}) {
            if (side < m) m = side;
        }
        crosses[i] = true;
        plane_t[i] = t;
        inside[i] = m;
        if (m >= 0 && (!best.hit || t < best.t)) {
            best.hit = true;
            best.rect = i;
            best.t = t;
        }
    }
    for (int i = 0; i < n && i < kMaxRects; ++i) {
        if (crosses[i] && (!best.hit || plane_t[i] <= best.t) && abs_q(inside[i]) <= quad(kEdgeBand)) {
            best.near_edge = true;
        }
        if (crosses[i] && best.hit && i != best.rect && plane_t[i] == best.t && inside[i] >= 0) best.tie = i;
    }
    return best;
}

double ulps(quad exact, double got, int bits) {
    if (!std::isfinite(got)) return std::numeric_limits<double>::infinity();
    const int min_exponent = bits == 24 ? -126 : -1022;  // below it the spacing is fixed
    int e = 0;
    std::frexp(static_cast<double>(exact), &e);          // |exact| in [2^(e-1), 2^e)
    int exponent = e - 1;
    if (exponent < min_exponent) exponent = min_exponent;
    const quad ulp = scalbnq(quad(1), exponent - (bits - 1));
    return static_cast<double>(abs_q(quad(got) - exact) / ulp);
}

}  // namespace raykit::bench
