// The scripted stand-in for a step a graded step needs (issue 43): what the judge and the answers
// program say to each other about it.
//
// Where the reference is present (a grading), step 05 is never linked with the reference's step 04:
// no solution code may sit in a process the student's code runs in, where it could be read byte by
// byte or asked questions of the student's own choosing. Nor with the student's own step 04: a slip
// there would cost step 05 too, and a platform that grades a step alone (PrairieLearn's questions)
// has no step 04 to link. Instead the answers program of step 05 holds a stand-in for intersect_rect
// (standin_04.cpp) that knows only what the judge told it before each call, its *script*: for each
// ray the call may cast and each object of the call's scene, where the ray's line meets that
// rectangle (the reference's answer with an unbounded window), or that it does not. A call of
// find_intersection casts the case's own ray; a call of render casts one view ray per pixel, which
// the judge asks of the student's own view_ray, in the student's process, before it asks the
// reference where each meets each object. The stand-in answers from the script for any window the
// student's loop asks about, a ray whose direction is a positive multiple of a scripted one included
// (a view ray normalised, or computed in the loop in another order), and refuses any other question.
//
// What the student's process holds, then, is its own: the case's input, its own view rays, and for
// each, step 04's answer, which intersect_rect would give it anyway. No reference answer of a step 05
// function is in it (issue 52: when the script held the reference's view rays, a render could read
// them out of its own memory and pass with view_ray the stub; tests/fixtures/hostile/read_script).
// The price: the render cases wait on the student's view_ray (a wrong one fails the picture anyway).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "raykit/ray.hpp"
#include "raykit/rect.hpp"
#include "wire.hpp"

namespace raykit::standin {

/// The wire name of the script message. Not an identifier: no step function can be called so.
inline constexpr const char* message = "raykit.script";

/// What the script is for, named in the stand-in's refusal.
enum class For : std::uint8_t {
    find_intersection = 0,  ///< the case's own ray
    render = 1,             ///< the student's view ray of each pixel
};

/// One ray of a script and, for each object of the scene in order, where its line meets that
/// object's rectangle (any window), or never (empty).
struct Line {
    Ray ray;
    std::vector<std::optional<float>> t;
};

/// The message's payload: what it is for, the scene's rectangles, then the rays with their answers.
inline std::string encode(For what, const std::vector<Rect>& rects, const std::vector<Line>& lines) {
    wire::Writer w;
    w.raw(static_cast<std::uint8_t>(what));
    wire::put(w, rects);
    w.raw(static_cast<std::uint32_t>(lines.size()));
    for (const Line& l : lines) {
        wire::put(w, l.ray);
        wire::put(w, l.t);
    }
    return w.bytes;
}

/// The answers program's receiver of a script (set by the stand-in's object when it is linked; none
/// in a program without a stand-in, which then says it has no such function).
using Receiver = void (*)(wire::Reader&);
extern Receiver receiver;

/// The wire name of the judge's one question to the *reference's* program for a whole script: the
/// scene's rectangles and the rays, answered with where each ray's line meets each rectangle (rays
/// in order, objects in order within a ray). One call a case instead of one a ray and object: those
/// round trips were most of a step 05 judge's CPU (docs/performance.md).
inline constexpr const char* lines_message = "raykit.lines";

/// The reference's answerer of lines_message (script_04.cpp, linked into the reference's answers
/// program only). None in a student's program, which then says it has no such function: the
/// question and its answer never reach the student's process.
using LinesServer = void (*)(wire::Reader&, wire::Writer&);
extern LinesServer lines_server;

}  // namespace raykit::standin
