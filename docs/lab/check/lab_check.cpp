// The C++ side of the lab's self-test (tools/kitlib/selftest/lab.py): for each line of float
// inputs read from the lab page, the answers the kit computes in C++, to compare with the page's.
//
// Input, one case a line: a name and seven float bit patterns in hex,
//   NAME ox oy dx dy cx cy r          (z = 0: the lab draws the plane of the ray and the centre)
// Output, one line a case:
//   NAME exact N t0 t1 | solution N t0 t1 | textbook N t0 t1 | ulps U0 U1 | FORM N t0 t1 U0 U1 ...
// where each FORM is one more row of the page's table (textbook-f64, halfb-f32, halfb-f64,
// rewrite-f32, rewrite-f64, lagrange-f32, lagrange-f64), computed below with the page's operations
// in the page's order, in float or in double (a double row's roots rounded to float at the end, as
// the page does), and U0 U1 their ulp_distance from the exact roots (-1 -1 when the counts differ
// or there is no root).
// with the floats as hex bit patterns:
//   exact:    tests/support/reference_roots.hpp, 113-bit, rounded to float (sphere_roots_rounded);
//   solution: the reference solution's sphere_roots (solutions/02_general_sphere);
//   textbook: the float textbook formula below, built with -ffp-contract=off (no fused multiply-add);
//   ulps:     tests/support/ulps.hpp's ulp_distance of the textbook roots from the exact ones
//             (-1 when the counts differ).
//
// Instructor-only (the handout leaves docs/lab/check/ out): it computes a step's answer.

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <sstream>
#include <string>

#include "raykit/general_sphere.hpp"
#include "reference_roots.hpp"
#include "ulps.hpp"

namespace {

float from_bits(std::uint32_t b) {
    float x;
    std::memcpy(&x, &b, sizeof x);
    return x;
}

std::uint32_t bits(float x) {
    std::uint32_t b;
    std::memcpy(&b, &x, sizeof b);
    return b;
}

// The textbook formula of lecture 01, section 3, in float, one rounding per operation, in the
// order the lab's JavaScript writes it (glm's dot: (x x + y y) + z z).
raykit::Roots textbook(const raykit::Ray& ray, const raykit::Sphere& sphere) {
    const glm::vec3 f = ray.origin - sphere.center;
    const glm::vec3 d = ray.direction;
    const float a = d.x * d.x + d.y * d.y + d.z * d.z;
    const float b = 2.0f * (f.x * d.x + f.y * d.y + f.z * d.z);
    const float c = (f.x * f.x + f.y * f.y + f.z * f.z) - sphere.radius * sphere.radius;
    const float disc = b * b - 4.0f * a * c;
    if (!(a > 0.0f) || !(sphere.radius > 0.0f) || !(disc >= 0.0f)) return {};
    if (disc == 0.0f) {
        const float t = -b / (2.0f * a);
        return {1, {t, t}};
    }
    const float s = std::sqrt(disc);
    float t0 = (-b - s) / (2.0f * a);
    float t1 = (-b + s) / (2.0f * a);
    if (std::isnan(t0) || std::isnan(t1)) return {};
    if (t0 > t1) std::swap(t0, t1);
    return {2, {t0, t1}};
}

// The page's four formulas (docs/lab/lab.js, "the formulas"), in T = float or double, with the
// vectors in the plane (z = 0) and glm's order of operations: dot (x x + y y) + z z.
template <typename T>
struct V3 { T x, y, z; };
template <typename T>
T dot3(const V3<T>& u, const V3<T>& v) { return (u.x * v.x + u.y * v.y) + u.z * v.z; }
template <typename T>
V3<T> sub3(const V3<T>& u, const V3<T>& v) { return {u.x - v.x, u.y - v.y, u.z - v.z}; }

template <typename T>
struct Inputs {
    V3<T> o, d, c;
    T r;
};
template <typename T>
Inputs<T> inputs(const raykit::Ray& ray, const raykit::Sphere& s) {
    return {{T(ray.origin.x), T(ray.origin.y), T(0)}, {T(ray.direction.x), T(ray.direction.y), T(0)},
            {T(s.center.x), T(s.center.y), T(0)}, T(s.radius)};
}
int count_of(double disc) { return disc > 0 ? 2 : disc == 0 ? 1 : 0; }   // NaN: 0

template <typename T>
raykit::Roots pair(T t0, T t1) {          // rounded to float, as a kit function returns them
    if (std::isnan(t0) || std::isnan(t1)) return {};
    if (t0 > t1) std::swap(t0, t1);
    return {2, {static_cast<float>(t0), static_cast<float>(t1)}};
}
template <typename T>
raykit::Roots one(T t) { return {1, {static_cast<float>(t), static_cast<float>(t)}}; }

template <typename T>
raykit::Roots textbook_in(const Inputs<T>& v) {
    const V3<T> f = sub3(v.o, v.c);
    const T a = dot3(v.d, v.d);
    const T b = T(2) * dot3(f, v.d);
    const T c = dot3(f, f) - v.r * v.r;
    const T disc = b * b - (T(4) * a) * c;
    if (!(a > 0) || !(v.r > 0)) return {};
    const int n = count_of(disc);
    if (n == 0) return {};
    const T sq = std::sqrt(disc), den = T(2) * a;
    if (n == 1) return one(T(-b) / den);
    return pair((-b - sq) / den, (-b + sq) / den);
}
template <typename T>
raykit::Roots halfb_in(const Inputs<T>& v) {
    const V3<T> f = sub3(v.o, v.c);
    const T a = dot3(v.d, v.d), h = dot3(f, v.d);
    const T c = dot3(f, f) - v.r * v.r;
    const T d4 = h * h - a * c;
    if (!(a > 0) || !(v.r > 0)) return {};
    const int n = count_of(d4);
    if (n == 0) return {};
    if (n == 1) return one(T(-h) / a);
    const T sq = std::sqrt(d4);
    return pair((-h - sq) / a, (-h + sq) / a);
}
template <typename T>
raykit::Roots rewrite_in(const Inputs<T>& v) {
    const V3<T> f = sub3(v.o, v.c);
    const T a = dot3(v.d, v.d), h = dot3(f, v.d);
    const T c = dot3(f, f) - v.r * v.r;
    if (!(a > 0) || !(v.r > 0)) return {};
    const T k = h / a;
    const V3<T> leg = sub3(f, V3<T>{k * v.d.x, k * v.d.y, k * v.d.z});
    const T d4 = a * (v.r * v.r - dot3(leg, leg));
    const int n = count_of(d4);
    if (n == 0) return {};
    if (n == 1) return one(T(-h) / a);
    const T q = -(h + std::copysign(std::sqrt(d4), h));
    return pair(q / a, c / q);
}
template <typename T>
raykit::Roots lagrange_in(const Inputs<T>& v) {
    const V3<T> f = sub3(v.o, v.c);
    const T a = dot3(v.d, v.d), h = dot3(f, v.d);
    if (!(a > 0) || !(v.r > 0)) return {};
    const V3<T> g{f.y * v.d.z - v.d.y * f.z, f.z * v.d.x - v.d.z * f.x, f.x * v.d.y - v.d.x * f.y};
    const T d4 = a * (v.r * v.r) - dot3(g, g);
    const int n = count_of(d4);
    if (n == 0) return {};
    if (n == 1) return one(T(-h) / a);
    const T sq = std::sqrt(d4);
    return pair((-h - sq) / a, (-h + sq) / a);
}

void put_row(const char* what, const raykit::Roots& r, const raykit::Roots& exact) {
    std::printf(" | %s %d %08x %08x", what, r.count, r.count ? bits(r.t[0]) : 0u, r.count ? bits(r.t[1]) : 0u);
    if (r.count == exact.count && r.count > 0)
        std::printf(" %lld %lld", static_cast<long long>(raykit::grading::ulp_distance(r.t[0], exact.t[0])),
                    static_cast<long long>(raykit::grading::ulp_distance(r.t[1], exact.t[1])));
    else
        std::printf(" -1 -1");
}

void put(const char* what, const raykit::Roots& r) {
    std::printf(" %s %d %08x %08x", what, r.count, r.count ? bits(r.t[0]) : 0u,
                r.count ? bits(r.t[1]) : 0u);
}

}  // namespace

int main() {
    std::string line;
    while (std::getline(std::cin, line)) {
        std::istringstream in(line);
        std::string name;
        std::uint32_t v[7];
        if (!(in >> name)) continue;
        for (auto& x : v) {
            if (!(in >> std::hex >> x)) {
                std::fprintf(stderr, "lab_check: %s: expected 7 hex floats\n", name.c_str());
                return 2;
            }
        }
        const raykit::Ray ray{{from_bits(v[0]), from_bits(v[1]), 0.0f}, {from_bits(v[2]), from_bits(v[3]), 0.0f}};
        const raykit::Sphere sphere{{from_bits(v[4]), from_bits(v[5]), 0.0f}, from_bits(v[6])};
        const raykit::Roots exact = raykit::reference::sphere_roots_rounded(ray, sphere);
        const raykit::Roots book = textbook(ray, sphere);
        std::printf("%s", name.c_str());
        put("exact", exact);
        put("| solution", raykit::sphere_roots(ray, sphere));
        put("| textbook", book);
        if (book.count == exact.count && book.count > 0) {
            std::printf(" | ulps %lld %lld",
                        static_cast<long long>(raykit::grading::ulp_distance(book.t[0], exact.t[0])),
                        static_cast<long long>(raykit::grading::ulp_distance(book.t[1], exact.t[1])));
        } else {
            std::printf(" | ulps -1 -1");
        }
        const Inputs<float> in32 = inputs<float>(ray, sphere);
        const Inputs<double> in64 = inputs<double>(ray, sphere);
        put_row("textbook-f64", textbook_in(in64), exact);
        put_row("halfb-f32", halfb_in(in32), exact);
        put_row("halfb-f64", halfb_in(in64), exact);
        put_row("rewrite-f32", rewrite_in(in32), exact);
        put_row("rewrite-f64", rewrite_in(in64), exact);
        put_row("lagrange-f32", lagrange_in(in32), exact);
        put_row("lagrange-f64", lagrange_in(in64), exact);
        std::printf("\n");
    }
    return 0;
}
