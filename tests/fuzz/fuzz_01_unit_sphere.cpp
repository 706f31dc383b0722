// libFuzzer target: step 01's reference functions on arbitrary float bit patterns
// (NaN, infinities, subnormals included), checked with the property oracles.

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "../properties/oracles.hpp"
#include "raykit/unit_sphere.hpp"

using namespace raykit;

namespace {

[[noreturn]] void broken(const char* what, const Ray& r, float tmin, float tmax) {
    std::fprintf(stderr, "property broken: %s\n  o = (%a, %a, %a) d = (%a, %a, %a) window [%a, %a]\n", what,
                 r.origin.x, r.origin.y, r.origin.z, r.direction.x, r.direction.y, r.direction.z, tmin, tmax);
    std::abort();
}

bool moderate(const glm::vec3& v, float lo, float hi) {
    const float len = glm::length(v);
    return oracles::finite(v) && len <= hi && len >= lo;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    float f[8];
    if (size < sizeof f) return 0;
    std::memcpy(f, data, sizeof f);
    const Ray ray{{f[0], f[1], f[2]}, {f[3], f[4], f[5]}};
    const float tmin = f[6], tmax = f[7];

    const Roots r = unit_sphere_roots(ray);
    if (std::string e = oracles::roots_well_formed(r); !e.empty()) broken(e.c_str(), ray, tmin, tmax);
    const std::optional<float> hit = intersect_unit_sphere(ray, tmin, tmax);
    if (std::string e = oracles::hit_in_window(r, tmin, tmax, hit); !e.empty()) broken(e.c_str(), ray, tmin, tmax);

    // Geometry is only checked where float can represent the quantities involved: the squares of
    // the inputs must not overflow or vanish (the documented domain of the functions).
    if (moderate(ray.origin, 0, 1e6f) && moderate(ray.direction, 1e-6f, 1e6f)) {
        if (std::string e = oracles::roots_classified(ray, glm::vec3(0), 1.0f, r); !e.empty())
            broken(e.c_str(), ray, tmin, tmax);
        for (int i = 0; i < r.count; ++i)
            if (std::string e = oracles::root_on_surface(ray, glm::vec3(0), 1.0f, r.t[i]); !e.empty())
                broken(e.c_str(), ray, tmin, tmax);
    }
    return 0;
}
