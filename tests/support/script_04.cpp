// The reference's side of a step 05 script (standin.hpp): where each of a case's rays meets each of
// its objects, asked once a case. Linked into the reference's answers program only (CMakeLists.txt),
// so a student's program has no answerer and refuses the question.

#include <limits>
#include <optional>
#include <vector>

#include "raykit/rect.hpp"
#include "standin.hpp"

namespace raykit::standin {

namespace {

void serve_lines(wire::Reader& in, wire::Writer& out) {
    const std::vector<Rect> rects = wire::get<std::vector<Rect>>(in);
    const std::vector<Ray> rays = wire::get<std::vector<Ray>>(in);
    if (!in.at_end()) throw wire::wire_error("a lines question longer than its rays");
    if (!rects.empty() && rays.size() > wire::max_items / rects.size())
        throw wire::wire_error("a lines question too long");
    const float inf = std::numeric_limits<float>::infinity();
    std::vector<std::optional<float>> t;
    t.reserve(rays.size() * rects.size());
    for (const Ray& ray : rays)
        for (const Rect& rect : rects) t.push_back(intersect_rect(ray, rect, -inf, inf));
    wire::put(out, t);
}

[[maybe_unused]] const bool registered = (lines_server = serve_lines, true);

}  // namespace

}  // namespace raykit::standin
