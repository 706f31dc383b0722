// libFuzzer target: step 04's reference intersect_rect on arbitrary float bit patterns.

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "../properties/rect_oracle.hpp"

using namespace raykit;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    float f[13];
    if (size < sizeof f + 1) return 0;
    std::memcpy(f, data, sizeof f);
    const Ray ray{{f[0], f[1], f[2]}, {f[3], f[4], f[5]}};
    const Rect rect{static_cast<int>(data[sizeof f] % 5) - 1, f[6], {f[7], f[8]}, {f[9], f[10]}};  // axis -1..3
    const float tmin = f[11], tmax = f[12];
    const std::optional<float> hit = intersect_rect(ray, rect, tmin, tmax);
    // The oracle's margins assume moderate numbers; beyond them only the contract is checked.
    bool moderate = true;
    for (float x : f) moderate = moderate && std::isfinite(x) && std::fabs(x) < 1e6f;
    const std::string e = moderate ? oracles::rect_agrees(ray, rect, tmin, tmax, hit)
                          : (hit && (std::isnan(*hit) || !(tmin <= *hit && *hit <= tmax))) ? "a NaN hit or a hit outside the window"
                                                                                           : std::string();
    if (!e.empty()) {
        std::fprintf(stderr, "property broken: %s\n  o = (%a, %a, %a) d = (%a, %a, %a) rect axis %d offset %a "
                             "lo (%a, %a) hi (%a, %a) window [%a, %a]\n", e.c_str(), f[0], f[1], f[2], f[3], f[4],
                     f[5], rect.axis, f[6], f[7], f[8], f[9], f[10], tmin, tmax);
        std::abort();
    }
    return 0;
}
