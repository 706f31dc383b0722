// The judge's stand-ins for a step's functions: each sends its call to the
// answers process (remote.hpp) and returns what comes back. Compiled once per
// step with RAYKIT_REMOTE_LIST naming the step's list of functions (written by
// CMake from step.json and the headers, cmake/StepManifest.cmake).

#include <tuple>

// The declarations of every step function: each header of include/raykit/, listed by CMake.
#include RAYKIT_API_HEADERS
#include "case_figure.hpp"
#include "remote.hpp"

namespace raykit {

namespace {

#ifndef RAYKIT_REFERENCE_EXE
#define RAYKIT_REFERENCE_EXE ""
#endif
[[maybe_unused]] const bool programs_known = remote::set_built_programs(RAYKIT_ANSWERS_EXE, RAYKIT_REFERENCE_EXE);

template <class R, class... A>
R forward_call(const char* function, const std::tuple<A...>& args) {
    // Noted before the call, so that a failing check can draw it (case_figure.hpp).
    std::apply([&](const auto&... a) { figure::note_call(function, a...); }, args);
    return std::apply([&](const auto&... a) { return remote::call<R>(remote::Target::student, function, a...); },
                      args);
}

}  // namespace

// `ret name(params)` sends (args) to the student's answers process.
#define RAYKIT_REMOTE(ret, name, params, args) \
    ret name params { return forward_call<ret>(#name, std::forward_as_tuple args); }
#include RAYKIT_REMOTE_LIST
#undef RAYKIT_REMOTE

}  // namespace raykit
