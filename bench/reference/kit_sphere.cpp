// The kit's sphere code as a benchmark subject. See kit.hpp.
//
// RAYKIT_BENCH_SPHERE_STEP is set by bench/CMakeLists.txt: 2 when step 02 is
// built, 1 when only step 01 is, 0 when neither is.

#include "kit.hpp"

#if RAYKIT_BENCH_SPHERE_STEP == 2
#include "raykit/general_sphere.hpp"
#elif RAYKIT_BENCH_SPHERE_STEP == 1
#include "raykit/unit_sphere.hpp"
#endif

namespace raykit::bench::kit {

int sphere_step() { return RAYKIT_BENCH_SPHERE_STEP; }

Roots sphere_roots(const Ray& ray, const Sphere& sphere) {
#if RAYKIT_BENCH_SPHERE_STEP == 2
    return raykit::sphere_roots(ray, sphere);
#elif RAYKIT_BENCH_SPHERE_STEP == 1
    // |o + t d - c| = r is |o' + t d'| = 1 with o' = (o - c)/r and d' = d/r:
    // the same t, on the unit sphere at the origin. The move and the scaling
    // round, so this is step 01's method plus two roundings per coordinate.
    const Ray local{(ray.origin - sphere.center) / sphere.radius, ray.direction / sphere.radius};
    return unit_sphere_roots(local);
#else
    (void)ray;
    (void)sphere;
    return {};
#endif
}

}  // namespace raykit::bench::kit
