// The judge's stand-ins for a step's functions: each sends its call to the
// answers process (remote.hpp) and returns what comes back. Compiled once per
// step with RAYKIT_REMOTE_LIST naming the step's list of functions (written by
// CMake from step.json and the headers, cmake/StepManifest.cmake).

#include <cstring>
#include <limits>
#include <tuple>
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
// The student's step 05 runs on a stand-in for step 04 (standin.hpp): before each call the stand-in
// is told what to answer. A call of find_intersection: where the case's ray meets each of the scene's
// rectangles, from the reference's own program (never from the student's process); a call of
// render: the student's own step 04. Other calls need no script.
template <class... A>
void prepare(const char*, const A&...) {}

void send(standin::Mode mode, const std::vector<standin::Line>& lines) {
    remote::exchange(remote::Target::student, standin::message, standin::encode(mode, lines), "the case's script");
}

void prepare(const char* function, const Ray& ray, const Scene& scene, float, float) {
    if (std::strcmp(function, "find_intersection") != 0) return;
    const float inf = std::numeric_limits<float>::infinity();
    std::vector<standin::Line> lines;
    for (const Object& o : scene.objects)
        lines.push_back({ray, o.shape, remote::reference<std::optional<float>>("intersect_rect", ray, o.shape, -inf, inf)});
    send(standin::Mode::script, lines);
}

void prepare(const char* function, const Scene&, const Camera&) {
    if (std::strcmp(function, "render") == 0) send(standin::Mode::own, {});
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

// `ret name(params)` sends (args) to the student's answers process.
#define RAYKIT_REMOTE(ret, name, params, args) \
    ret name params { return forward_call<ret>(#name, std::forward_as_tuple args); }
#include RAYKIT_REMOTE_LIST
#undef RAYKIT_REMOTE

}  // namespace raykit
