// libFuzzer target: step 02's reference functions on arbitrary float bit patterns.

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "../properties/oracles.hpp"
#include "raykit/general_sphere.hpp"

using namespace raykit;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    float f[12];
    if (size < sizeof f) return 0;
    std::memcpy(f, data, sizeof f);
    const Ray ray{{f[0], f[1], f[2]}, {f[3], f[4], f[5]}};
    const Sphere s{{f[6], f[7], f[8]}, f[9]};
    const float tmin = f[10], tmax = f[11];
    const Roots r = sphere_roots(ray, s);
    std::string e = oracles::roots_well_formed(r);
    if (e.empty()) e = oracles::hit_in_window(r, tmin, tmax, intersect_sphere(ray, s, tmin, tmax));
    // Geometry where float represents the inputs' squares (the documented domain).
    bool moderate = s.radius >= 1e-3f && s.radius <= 1e4f && glm::length(ray.direction) >= 1e-3f &&
                    glm::length(ray.direction) <= 1e3f;
    for (int i = 0; i < 9; ++i) moderate = moderate && std::isfinite(f[i]) && std::fabs(f[i]) <= 1e5f;
    if (e.empty() && moderate && glm::length(ray.origin - s.center) <= 1e3f * s.radius) {
        e = oracles::roots_classified(ray, s.center, s.radius, r);
        for (int k = 0; k < r.count && e.empty(); ++k) e = oracles::root_on_surface(ray, s.center, s.radius, r.t[k]);
    }
    if (!e.empty()) {
        std::fprintf(stderr, "property broken: %s\n  o = (%a, %a, %a) d = (%a, %a, %a) c = (%a, %a, %a) r = %a "
                             "window [%a, %a]\n", e.c_str(), f[0], f[1], f[2], f[3], f[4], f[5], f[6], f[7], f[8],
                     f[9], tmin, tmax);
        std::abort();
    }
    return 0;
}
