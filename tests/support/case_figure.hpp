// The geometry of a failing sphere or rectangle case, for the picture the kit
// draws of it (tools/raykit/picture/).
//
// Why here and not in the suites: every sphere and rectangle case already ends
// in check_roots or check_hit (grading.hpp), and every call to the student's
// code already goes through a proxy (proxies.cpp). The proxy notes the
// arguments of the last call; the check, when it fails, adds the expected answer
// and the student's and keeps the record. The reporter writes it with the case
// ("figure" in the end event) and forgets it when the next case begins. So no
// case needs editing, and the judge still only sees the answers that came back
// over the wire.
//
// Only calls whose arguments are all drawable (a ray, a sphere, a rectangle,
// floats for the window) are noted: the step 05 calls (a scene, a camera) clear
// the note, so a later check cannot draw the wrong call. A case records at most
// one figure: that of its first failing check, which is also its first message.
#pragma once

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "float_text.hpp"
#include "raykit/ray.hpp"
#include "raykit/rect.hpp"
#include "raykit/roots.hpp"
#include "raykit/sphere.hpp"

namespace raykit::figure {

/// A float as JSON: a number when finite; "inf", "-inf" or "NaN" as a string,
/// which JSON has no number for (Python's float() reads all three back).
inline std::string json(float x) {
    const std::string text = float_text(x);
    return std::isfinite(x) ? text : "\"" + text + "\"";
}

inline std::string json(const glm::vec3& v) { return "[" + json(v.x) + ", " + json(v.y) + ", " + json(v.z) + "]"; }
inline std::string json(const glm::vec2& v) { return "[" + json(v.x) + ", " + json(v.y) + "]"; }

inline std::string json(const Roots& r) {
    // The count as sent, even when it is not 0, 1 or 2: the picture says so.
    return "{\"count\": " + std::to_string(r.count) + ", \"t\": [" + json(r.t[0]) + ", " + json(r.t[1]) + "]}";
}

inline std::string json(const std::optional<float>& hit) { return hit ? json(*hit) : "null"; }

/// The arguments of one call, as the picture needs them.
struct Arguments {
    bool drawable = true;
    bool has_ray = false;         // a call without a ray (cornell_box()) draws nothing
    std::string fields;           // "ray": ..., "sphere": ... (JSON members, comma-separated)
    std::vector<float> window;    // the float arguments in order: tmin, tmax
};

inline void add_field(Arguments& a, const std::string& member) {
    a.fields += (a.fields.empty() ? "" : ", ") + member;
}
inline void add(Arguments& a, const Ray& r) {
    a.has_ray = true;
    add_field(a, "\"ray\": {\"origin\": " + json(r.origin) + ", \"direction\": " + json(r.direction) + "}");
}
inline void add(Arguments& a, const Sphere& s) {
    add_field(a, "\"sphere\": {\"center\": " + json(s.center) + ", \"radius\": " + json(s.radius) + "}");
}
inline void add(Arguments& a, const Rect& r) {
    add_field(a, "\"rect\": {\"axis\": " + std::to_string(r.axis) + ", \"offset\": " + json(r.offset) +
                     ", \"lo\": " + json(r.lo) + ", \"hi\": " + json(r.hi) + "}");
}
inline void add(Arguments& a, float x) { a.window.push_back(x); }
/// Anything else (a scene, a camera, a pixel index) is not drawn.
template <class T>
void add(Arguments& a, const T&) { a.drawable = false; }

/// The last call the judge sent to the student's code in this case.
struct State {
    std::string function;   // "" when the last call is not drawable
    std::string arguments;  // its JSON members
    bool failed = false;    // a check of this case has failed already
    std::string record;     // the figure of the first failing check, or ""
};

inline State& state() {
    static State s;
    return s;
}

/// The reporter, when a case begins.
inline void begin_case() { state() = State{}; }

/// The proxies, before each call to the student's code.
template <class... A>
void note_call(const char* function, const A&... args) {
    Arguments a;
    (add(a, args), ...);
    State& s = state();
    if (!a.drawable || !a.has_ray || a.window.size() == 1 || a.window.size() > 2) {
        s.function.clear();
        s.arguments.clear();
        return;
    }
    s.function = function;
    s.arguments = a.fields;
    if (a.window.size() == 2)
        s.arguments += ", \"window\": [" + json(a.window[0]) + ", " + json(a.window[1]) + "]";
}

/// A check failed. `call` is the text the check names ("sphere_roots(ray, sphere)"):
/// its function must be the last call's, else the figure would show another call.
inline void note_failure(const std::string& call, const std::string& expected, const std::string& got) {
    State& s = state();
    if (s.failed) return;
    s.failed = true;
    const std::string function = call.substr(0, call.find('('));
    if (s.function.empty() || function != s.function) return;
    s.record = "{\"function\": \"" + s.function + "\", " + s.arguments + ", \"expected\": " + expected +
               ", \"got\": " + got + "}";
}

/// The reporter, when a case ends: the figure's JSON object, or "".
inline const std::string& record() { return state().record; }

}  // namespace raykit::figure
