// The judge's stand-ins for a step's functions: each sends its call to the
// answers process (remote.hpp) and returns what comes back. Compiled once per
// step with RAYKIT_REMOTE_LIST naming the step's list of functions (written by
// CMake from step.json and the headers, cmake/StepManifest.cmake).

#include <cstring>
#include <limits>
#include <optional>
#include <tuple>
#include <type_traits>
#include <vector>

// The declarations of every step function: each header of include/raykit/, listed by CMake.
#include RAYKIT_API_HEADERS
#include "case_figure.hpp"
#include "remote.hpp"
#ifdef RAYKIT_STANDIN
#include "standin.hpp"
#endif

namespace raykit {

namespace {

#ifndef RAYKIT_REFERENCE_EXE
#define RAYKIT_REFERENCE_EXE ""
#endif
[[maybe_unused]] const bool programs_known = remote::set_built_programs(RAYKIT_ANSWERS_EXE, RAYKIT_REFERENCE_EXE);

#ifdef RAYKIT_STANDIN
// The student's step 05 runs on a stand-in for step 04 (standin.hpp): before each call that may ask
// it something, the stand-in is told what to answer, its script, by the reference's own program:
// for find_intersection, where the case's ray meets each of the scene's rectangles; for render, the
// same for the view ray of each pixel that the *student's own* view_ray gives, asked of the student's
// process first, one ordinary call a pixel (so a crash, a hang, a throw or the stub is view_ray's,
// named as any call's). The script never holds a reference answer for a step 05 function: the case's
// ray is the case's input, the view rays are the student's, and where a ray meets a rectangle is
// step 04's answer, which intersect_rect gives anyway. (It once held the reference's view rays, which
// a render could read out of its own memory and score without a view_ray of its own: issue 52,
// tests/fixtures/hostile/read_script.) So the render cases wait on the student's view_ray. Other
// calls need no script.
template <class... A>
void prepare(const char*, const A&...) {}

void send(standin::For what, const Scene& scene, const std::vector<Ray>& rays) {
    std::vector<Rect> rects;
    for (const Object& o : scene.objects) rects.push_back(o.shape);
    // Where each ray meets each object, asked of the reference's own program in one question
    // (script_04.cpp): its answers come back to the judge, never through the student's process.
    wire::Writer question;
    wire::put(question, rects);
    wire::put(question, rays);
    std::vector<std::optional<float>> t;
    try {
        const std::string reply = remote::exchange(remote::Target::reference, standin::lines_message, question.bytes,
                                                   "the case's rays and objects");
        wire::Reader r(reply.data(), reply.size());
        t = wire::get<std::vector<std::optional<float>>>(r);
        if (!r.at_end() || t.size() != rays.size() * rects.size())
            throw wire::wire_error("not one answer per ray and object");
    } catch (const wire::wire_error& e) {
        throw remote::CallFailed(std::string("the reference's answers for the case's script cannot be read (") +
                                 e.what() + ")");
    }
    std::vector<standin::Line> lines;
    lines.reserve(rays.size());
    for (std::size_t i = 0; i < rays.size(); ++i)
        lines.push_back({rays[i], std::vector<std::optional<float>>(t.begin() + static_cast<std::ptrdiff_t>(i * rects.size()),
                                                                    t.begin() + static_cast<std::ptrdiff_t>((i + 1) * rects.size()))});
    remote::exchange(remote::Target::student, standin::message, standin::encode(what, rects, lines), "the case's script");
}

void prepare(const char* function, const Ray& ray, const Scene& scene, float, float) {
    if (std::strcmp(function, "find_intersection") == 0) send(standin::For::find_intersection, scene, {ray});
}

void prepare(const char* function, const Scene& scene, const Camera& camera) {
    if (std::strcmp(function, "render") != 0) return;
    // A canvas of no pixels or of more than any case draws (64 k pixels) has no view rays scripted:
    // the stand-in then refuses whatever it is asked.
    std::vector<Ray> rays;
    if (camera.width > 0 && camera.height > 0 && static_cast<long long>(camera.width) * camera.height <= (1 << 16)) {
        // Every pixel's view ray in one call of the student's process (answers_main.cpp's grid); where
        // that fails in any way, one call a pixel as before, which names the pixel that fails.
        const std::size_t pixels = static_cast<std::size_t>(camera.width) * static_cast<std::size_t>(camera.height);
        std::optional<std::vector<Ray>> all =
            remote::try_call<std::vector<Ray>>("raykit.grid.view_ray", camera, camera.width, camera.height);
        if (all && all->size() == pixels) {
            rays = std::move(*all);
        } else {
            rays.reserve(pixels);
            for (int j = 0; j < camera.height; ++j)
                for (int i = 0; i < camera.width; ++i)
                    rays.push_back(remote::call<Ray>(remote::Target::student, "view_ray", camera, i, j));
        }
    }
    send(standin::For::render, scene, rays);
}

/// The judge's own questions to step 04 (the model's cases find the object a ray sees first) go to
/// the reference: the student's process has only the stand-in.
remote::Target target_of(const char* function) {
    return std::strcmp(function, "intersect_rect") == 0 ? remote::Target::reference : remote::Target::student;
}
#else
template <class... A>
void prepare(const char*, const A&...) {}
remote::Target target_of(const char*) { return remote::Target::student; }
#endif

template <class R, class... A>
R forward_call(const char* function, const std::tuple<A...>& args) {
    // Noted before the call, so that a failing check can draw it (case_figure.hpp).
    std::apply([&](const auto&... a) { figure::note_call(function, a...); }, args);
    const remote::Target target = target_of(function);
    if (target == remote::Target::student) std::apply([&](const auto&... a) { prepare(function, a...); }, args);
    return std::apply([&](const auto&... a) { return remote::call<R>(target, function, a...); }, args);
}

}  // namespace

// `ret name(params)` sends (args) to the student's answers process. The signature comes from the
// step's manifest (step.json's "functions"); it must be the header's, or this would define an overload
// of its own and leave the declared function undefined: the assertion names the function instead.
#define RAYKIT_REMOTE(ret, name, params, args)                                                        \
    static_assert(std::is_same_v<decltype(&name), ret(*) params>,                                     \
                  "step.json's \"functions\" entry for " #name " has another signature than its header"); \
    ret name params { return forward_call<ret>(#name, std::forward_as_tuple args); }
#include RAYKIT_REMOTE_LIST
#undef RAYKIT_REMOTE

}  // namespace raykit
