// libFuzzer target: step 03's reference forms on arbitrary float bit patterns. The contract
// (well-formed roots, never NaN) holds for any input; the geometry is checked on unit rays.

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "../properties/oracles.hpp"
#include "raykit/unit_direction.hpp"

using namespace raykit;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    float f[10];
    if (size < sizeof f) return 0;
    std::memcpy(f, data, sizeof f);
    const Sphere s{{f[6], f[7], f[8]}, f[9]};
    bool moderate = s.radius >= 1e-3f && s.radius <= 1e4f;
    for (int i = 0; i < 9; ++i) moderate = moderate && std::isfinite(f[i]) && std::fabs(f[i]) <= 1e5f;
    glm::vec3 d{f[3], f[4], f[5]};
    const bool unit = moderate && glm::length(d) >= 1e-3f;
    if (unit) d = glm::normalize(d);
    const Ray ray{{f[0], f[1], f[2]}, d};
    for (const Roots& r : {sphere_roots_unit_dir(ray, s), sphere_roots_geometric(ray, s)}) {
        std::string e = oracles::roots_well_formed(r);
        if (e.empty() && unit && glm::length(ray.origin - s.center) <= 1e3f * s.radius) {
            e = oracles::roots_classified(ray, s.center, s.radius, r);
            for (int k = 0; k < r.count && e.empty(); ++k) e = oracles::root_on_surface(ray, s.center, s.radius, r.t[k]);
        }
        if (!e.empty()) {
            std::fprintf(stderr, "property broken: %s\n  o = (%a, %a, %a) d = (%a, %a, %a) c = (%a, %a, %a) r = %a\n",
                         e.c_str(), f[0], f[1], f[2], d.x, d.y, d.z, f[6], f[7], f[8], f[9]);
            std::abort();
        }
    }
    return 0;
}
