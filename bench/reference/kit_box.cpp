// The kit's rectangle and scene code as benchmark subjects. See kit.hpp.
//
// RAYKIT_BENCH_STEP04 and RAYKIT_BENCH_STEP05 are set to 1 by
// bench/CMakeLists.txt when those steps are built and this file compiles
// against their headers; otherwise the benchmark uses its own table and loop.

#include "kit.hpp"

#include <deque>
#include <limits>

#if RAYKIT_BENCH_STEP04
#include "raykit/rect.hpp"
#endif
#if RAYKIT_BENCH_STEP05
#include "raykit/cornell_box.hpp"
#include "raykit/render.hpp"
#endif

namespace raykit::bench::kit {

bool has_rect() { return RAYKIT_BENCH_STEP04 != 0; }
bool has_scene() { return RAYKIT_BENCH_STEP05 != 0; }

#if RAYKIT_BENCH_STEP05
namespace {
const Scene& the_scene() {
    static const Scene scene = cornell_box();
    return scene;
}
}  // namespace
#endif

std::vector<Rect3> box_table() {
#if RAYKIT_BENCH_STEP05
    std::vector<Rect3> table;
    for (const Object& object : the_scene().objects) {
        const Rect& r = object.shape;
        table.push_back({r.axis, r.offset, {r.lo.x, r.lo.y}, {r.hi.x, r.hi.y}});
    }
    return table;
#else
    return {kCornellBox, kCornellBox + kBoxRects};
#endif
}

#if RAYKIT_BENCH_STEP04
struct RectTable {
    std::vector<Rect> rects;
};

const RectTable* rect_table(const std::vector<Rect3>& rects) {
    static std::deque<RectTable> tables;  // stable addresses, kept to the end
    RectTable& t = tables.emplace_back();
    for (const Rect3& r : rects) t.rects.push_back({r.axis, r.offset, {r.lo[0], r.lo[1]}, {r.hi[0], r.hi[1]}});
    return &t;
}

BoxHit brute_force(const RectTable* table, const Ray& ray, float tmin) {
    BoxHit best;
    float tmax = std::numeric_limits<float>::infinity();
    for (std::size_t i = 0; i < table->rects.size(); ++i) {
        const std::optional<float> t = intersect_rect(ray, table->rects[i], tmin, tmax);
        if (t && (!best.hit || *t < tmax)) {  // on a tie the first listed wins, as in step 05
            tmax = *t;
            best = {true, static_cast<int>(i), *t};
        }
    }
    return best;
}
#else
struct RectTable {};
const RectTable* rect_table(const std::vector<Rect3>&) { return nullptr; }
BoxHit brute_force(const RectTable*, const Ray&, float) { return {}; }
#endif

#if RAYKIT_BENCH_STEP05
BoxHit find_intersection(const Ray& ray, float tmin) {
    const std::optional<Hit> hit =
        raykit::find_intersection(ray, the_scene(), tmin, std::numeric_limits<float>::infinity());
    if (!hit) return {};
    return {true, static_cast<int>(hit->index), hit->t};
}
#else
BoxHit find_intersection(const Ray&, float) { return {}; }
#endif

}  // namespace raykit::bench::kit
