// The stand-in for step 04's intersect_rect in a graded step 05 (see standin.hpp for why).
//
// The student's own step 04, when it is there and compiles, is linked beside it with its function
// renamed (raykit_own_intersect_rect, by a -D on its compile: CMakeLists.txt), for the picture cases.
// Without it, the weak definition below stands in: those cases then wait for step 04.

#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>

#include "raykit/not_implemented.hpp"
#include "raykit/rect.hpp"
#include "standin.hpp"

namespace raykit {

std::optional<float> raykit_own_intersect_rect(const Ray& ray, const Rect& rect, float tmin, float tmax);

// Weak: the student's own step 04, renamed, replaces it when it was compiled (GCC and Clang, ELF and
// Mach-O alike).
__attribute__((weak)) std::optional<float> raykit_own_intersect_rect(const Ray&, const Rect&, float, float) {
    throw not_implemented("intersect_rect (your step 04 is missing or does not compile)");
}

namespace standin {

namespace {

Mode mode = Mode::script;
std::vector<Line> lines;

void receive(wire::Reader& r) {
    const auto m = r.raw<std::uint8_t>();
    if (m > 1) throw wire::wire_error("an unknown stand-in mode");
    const auto n = r.raw<std::uint32_t>();
    if (n > wire::max_items) throw wire::wire_error("a script too long");
    std::vector<Line> got;
    got.reserve(n);
    for (std::uint32_t i = 0; i < n; ++i) got.push_back(get_line(r));
    mode = static_cast<Mode>(m);
    lines = std::move(got);
}

[[maybe_unused]] const bool registered = (receiver = receive, true);

/// Bit for bit: a NaN in the case's rectangle is the same NaN when passed on unchanged.
bool same_rect(const Rect& a, const Rect& b) {
    return a.axis == b.axis && std::memcmp(&a.offset, &b.offset, sizeof a.offset) == 0 &&
           std::memcmp(&a.lo, &b.lo, sizeof a.lo) == 0 && std::memcmp(&a.hi, &b.hi, sizeof a.hi) == 0;
}

/// Whether `ray` is `line`'s ray or the same ray with its direction scaled by k > 0 (a loop may
/// pass a copy, or a normalised direction); sets k. A t along `ray` is then t along `line` over k.
bool same_ray(const Ray& line, const Ray& ray, float& k) {
    if (std::memcmp(&line.origin, &ray.origin, sizeof ray.origin) != 0) return false;
    if (std::memcmp(&line.direction, &ray.direction, sizeof ray.direction) == 0) {
        k = 1.0f;
        return true;
    }
    const float dd = glm::dot(line.direction, line.direction);
    if (!(dd > 0.0f)) return false;
    k = glm::dot(ray.direction, line.direction) / dd;
    if (!(k > 0.0f) || !std::isfinite(k)) return false;
    const glm::vec3 off = ray.direction - k * line.direction;
    return glm::dot(off, off) <= 1e-12f * glm::dot(ray.direction, ray.direction);
}

}  // namespace

}  // namespace standin

std::optional<float> intersect_rect(const Ray& ray, const Rect& rect, float tmin, float tmax) {
    using namespace standin;
    if (mode == Mode::own) return raykit_own_intersect_rect(ray, rect, tmin, tmax);
    for (const Line& line : lines) {
        float k = 1.0f;
        if (!same_rect(line.rect, rect) || !same_ray(line.ray, ray, k)) continue;
        if (!line.t) return std::nullopt;
        const float t = k == 1.0f ? *line.t : *line.t / k;
        // The closed window of rect.hpp, tested as the lecture's form tests it.
        if (!(tmin <= t && t <= tmax)) return std::nullopt;
        return t;
    }
    throw std::invalid_argument(
        "while grading step 05 the grader answers intersect_rect only for the case's own ray and the case's "
        "objects; your code asked it about " + wire::text(ray) + " and " + wire::text(rect) +
        ". Pass the ray you were given (or a positive multiple of its direction) and each object's rectangle "
        "unchanged");
}

}  // namespace raykit
