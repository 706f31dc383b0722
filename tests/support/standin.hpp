// The scripted stand-in for a step a graded step needs (issue 43): what the judge and the answers
// program say to each other about it.
//
// Where the reference is present (a grading), step 05 is never linked with the reference's step 04:
// no solution code may sit in a process the student's code runs in, where it could be read byte by
// byte or asked questions of the student's own choosing. Instead the answers program of step 05 holds
// a stand-in for intersect_rect (standin_04.cpp) that knows only what the judge told it before each
// call, its *script*: for the case's own ray and each object of the case's scene, where the ray's
// line meets that rectangle (the reference's answer with an unbounded window), or that it does not.
// The stand-in answers from the script for any window the student's loop asks about, and refuses
// any other question. The picture cases (render) cannot be scripted, since the student's own view
// rays are the questions: for those the judge switches the stand-in to the student's own step 04,
// and those cases wait for step 04 when it is not done (tools/kitlib/waits.py).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "raykit/ray.hpp"
#include "raykit/rect.hpp"
#include "wire.hpp"

namespace raykit::standin {

/// The wire name of the script message. Not an identifier: no step function can be called so.
inline constexpr const char* message = "raykit.script";

/// What the stand-in answers with.
enum class Mode : std::uint8_t {
    script = 0,  ///< only the script's lines; any other question is refused
    own = 1,     ///< the student's own step 04 (the picture cases)
};

/// One line of a script: the ray's line meets `rect` at `t` (any window), or never (`t` empty).
struct Line {
    Ray ray;
    Rect rect;
    std::optional<float> t;
};

inline void put(wire::Writer& w, const Line& l) {
    wire::put(w, l.ray);
    wire::put(w, l.rect);
    wire::put(w, l.t);
}

inline Line get_line(wire::Reader& r) {
    Line l;
    l.ray = wire::get<Ray>(r);
    l.rect = wire::get<Rect>(r);
    l.t = wire::get<std::optional<float>>(r);
    return l;
}

/// The message's payload: the mode, then the lines.
inline std::string encode(Mode mode, const std::vector<Line>& lines) {
    wire::Writer w;
    w.raw(static_cast<std::uint8_t>(mode));
    w.raw(static_cast<std::uint32_t>(lines.size()));
    for (const Line& l : lines) put(w, l);
    return w.bytes;
}

/// The answers program's receiver of a script (set by the stand-in's object when it is linked; none
/// in a program without a stand-in, which then says it has no such function).
using Receiver = void (*)(wire::Reader&);
extern Receiver receiver;

}  // namespace raykit::standin
