// The benchmark's yardstick: answers computed in __float128 (113-bit
// significand, libquadmath's sqrtq) from exactly the same float inputs the
// variants see, and the error of a variant's answer in ulps of its type.
#pragma once

#include <cstdint>

#include "box.hpp"
#include "families.hpp"
#include "vec.hpp"

namespace raykit::bench {

__extension__ typedef __float128 quad;  // __extension__: GCC's type, not ISO C++

/// The exact roots of one sample, and how far it is from a tangent.
struct ExactSphere {
    bool hit = false;        ///< the line meets the sphere (a tangent counts)
    quad t[2] = {0, 0};      ///< the roots, sorted (when hit)
    double impact = 0;       ///< distance from the centre to the line, in radii
    /// |impact - 1| <= the family's band: too close to a tangent to call hit or miss.
    bool near_tangent = false;
};

ExactSphere exact_sphere(const Sample<float>& s, double band);

/// The first root in [0, inf), as a ray tracer with tmin = 0 sees it.
bool first_hit(const ExactSphere& e, quad& t);

/// The exact closest hit of a ray with the box's rectangles in [tmin, inf).
struct ExactBoxHit {
    bool hit = false;
    int rect = -1;
    quad t = 0;
    /// Another rectangle hit at exactly the same t (coplanar and overlapping),
    /// or -1. Either one is a right answer for a tracer that has no tie rule.
    int tie = -1;
    /// The ray passes within kEdgeBand of an edge of some rectangle it meets,
    /// so which rectangle it hits is a matter of rounding.
    bool near_edge = false;
};

/// The edge band in scene units (the box is 555 units wide; a float's ulp at
/// 555 is 6e-5).
constexpr double kEdgeBand = 1e-3;

/// At most this many rectangles (the box has 6).
constexpr int kMaxRects = 16;

ExactBoxHit exact_box(const Vec3<float>& o, const Vec3<float>& d, const Rect3* rects, int n,
                      float tmin);

/// |got - exact| in units in the last place of a float (bits = 24) or a double
/// (bits = 53) at the exact value. Infinite when got is not finite.
double ulps(quad exact, double got, int bits);

}  // namespace raykit::bench
