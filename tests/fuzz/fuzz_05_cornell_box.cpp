// libFuzzer target: step 05's reference find_intersection over the Cornell box, against the
// brute-force definition (the nearest of the objects' own hits, the first on a tie).

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "raykit/cornell_box.hpp"
#include "raykit/render.hpp"

using namespace raykit;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const Scene scene = cornell_box();
    float f[8];
    if (size < sizeof f) return 0;
    std::memcpy(f, data, sizeof f);
    const Ray ray{{f[0], f[1], f[2]}, {f[3], f[4], f[5]}};
    const float tmin = f[6], tmax = f[7];
    std::optional<Hit> expected;
    for (std::size_t k = 0; k < scene.objects.size(); ++k) {
        const auto t = intersect_rect(ray, scene.objects[k].shape, tmin, tmax);
        if (t && (!expected || *t < expected->t)) expected = Hit{*t, k};
    }
    const auto got = find_intersection(ray, scene, tmin, tmax);
    const bool same = got.has_value() == expected.has_value() &&
                      (!got || (got->t == expected->t && got->index == expected->index));
    if (!same || (got && (std::isnan(got->t) || !(tmin <= got->t && got->t <= tmax)))) {
        std::fprintf(stderr, "property broken: find_intersection is not the nearest hit in the window\n"
                             "  o = (%a, %a, %a) d = (%a, %a, %a) window [%a, %a]\n",
                     f[0], f[1], f[2], f[3], f[4], f[5], tmin, tmax);
        std::abort();
    }
    return 0;
}
