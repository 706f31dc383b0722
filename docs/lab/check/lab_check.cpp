// The C++ side of the lab's self-test (tools/kitlib/selftest/lab.py): for each line of float
// inputs read from the lab page, the answers the kit computes in C++, to compare with the page's.
//
// Input, one case a line: a name and seven float bit patterns in hex,
//   NAME ox oy dx dy cx cy r          (z = 0: the lab draws the plane of the ray and the centre)
// Output, one line a case:
//   NAME exact N t0 t1 | solution N t0 t1 | textbook N t0 t1 | ulps U0 U1
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
            std::printf(" | ulps %lld %lld\n",
                        static_cast<long long>(raykit::grading::ulp_distance(book.t[0], exact.t[0])),
                        static_cast<long long>(raykit::grading::ulp_distance(book.t[1], exact.t[1])));
        } else {
            std::printf(" | ulps -1 -1\n");
        }
    }
    return 0;
}
