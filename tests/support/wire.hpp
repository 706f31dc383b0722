// The wire between the judge (the test program, which decides verdicts) and the
// answers process (the student's functions and nothing else).
//
// Why a wire at all: a student's code runs in its own process, inside a sandbox
// when the kit grades a folder it did not write, so that nothing it does — crash,
// loop, print, write files, rewrite the verdict output — can reach the process
// that judges. That process only ever sees the *answers*, as bytes, and checks
// them like any other untrusted input (a count of 7, a NaN, a canvas of the wrong
// size are all reported, never trusted).
//
// Format: a request is  u32 length | u8 name length | name | arguments;
// a reply is            u32 length | u8 kind | payload.
// Values are written in the machine's own byte order (both ends are built by one
// compiler on one machine). Every read is bounds-checked: a short or garbled
// reply becomes a wire_error, which the judge reports as the call's failure.
#pragma once

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "float_text.hpp"
#include "raykit/camera.hpp"
#include "raykit/canvas.hpp"
#include "raykit/ray.hpp"
#include "raykit/rect.hpp"
#include "raykit/roots.hpp"
#include "raykit/scene.hpp"
#include "raykit/sphere.hpp"

namespace raykit::wire {

/// A reply that does not decode: too short, too long, a size beyond the limits.
struct wire_error : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// What the answers process says about one call.
enum class Kind : std::uint8_t {
    value = 0,            ///< the function returned; its value follows
    not_implemented = 1,  ///< a stub: raykit::not_implemented was thrown (message follows)
    threw = 2,            ///< another exception (type and message follow)
    unknown = 3,          ///< no such function in this step (a kit bug, not the student's)
};

/// Largest string and list the judge accepts from the student's side.
constexpr std::uint32_t max_string = 1u << 16;
constexpr std::uint32_t max_items = 1u << 20;

// ---- writing ------------------------------------------------------------------

class Writer {
public:
    template <class T>
    void raw(const T& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        const char* p = reinterpret_cast<const char*>(&v);
        bytes.append(p, sizeof v);
    }
    std::string bytes;
};

inline void put(Writer& w, float v) { w.raw(v); }
inline void put(Writer& w, int v) { w.raw(static_cast<std::int32_t>(v)); }
inline void put(Writer& w, std::size_t v) { w.raw(static_cast<std::uint64_t>(v)); }
inline void put(Writer& w, const std::string& s) {
    w.raw(static_cast<std::uint32_t>(s.size()));
    w.bytes += s;
}
inline void put(Writer& w, const glm::vec2& v) { put(w, v.x), put(w, v.y); }
inline void put(Writer& w, const glm::vec3& v) { put(w, v.x), put(w, v.y), put(w, v.z); }
inline void put(Writer& w, const Ray& r) { put(w, r.origin), put(w, r.direction); }
inline void put(Writer& w, const Sphere& s) { put(w, s.center), put(w, s.radius); }
inline void put(Writer& w, const Rect& r) { put(w, r.axis), put(w, r.offset), put(w, r.lo), put(w, r.hi); }
inline void put(Writer& w, const Roots& r) { put(w, r.count), put(w, r.t[0]), put(w, r.t[1]); }
inline void put(Writer& w, const Hit& h) { put(w, h.t), put(w, h.index); }
inline void put(Writer& w, const Object& o) { put(w, o.name), put(w, o.shape), put(w, o.color); }
inline void put(Writer& w, const Camera& c) {
    put(w, c.eye), put(w, c.forward), put(w, c.up), put(w, c.focal_length), put(w, c.film_height);
    put(w, c.width), put(w, c.height);
}
template <class T>
void put(Writer& w, const std::vector<T>& items) {
    w.raw(static_cast<std::uint32_t>(items.size()));
    for (const T& item : items) put(w, item);
}
inline void put(Writer& w, const Scene& s) { put(w, s.objects); }
inline void put(Writer& w, const Canvas& c) {
    put(w, c.width()), put(w, c.height());
    for (int j = 0; j < c.height(); ++j)
        for (int i = 0; i < c.width(); ++i) put(w, c.at(i, j));
}
template <class T>
void put(Writer& w, const std::optional<T>& v) {
    w.raw(static_cast<std::uint8_t>(v.has_value()));
    if (v) put(w, *v);
}

// ---- reading --------------------------------------------------------------------

class Reader {
public:
    Reader(const char* data, std::size_t size) : p_(data), end_(data + size) {}

    template <class T>
    T raw() {
        static_assert(std::is_trivially_copyable_v<T>);
        if (static_cast<std::size_t>(end_ - p_) < sizeof(T)) throw wire_error("the reply is too short");
        T v;
        std::memcpy(&v, p_, sizeof v);
        p_ += sizeof v;
        return v;
    }
    std::string bytes(std::size_t n) {
        if (static_cast<std::size_t>(end_ - p_) < n) throw wire_error("the reply is too short");
        std::string s(p_, n);
        p_ += n;
        return s;
    }
    bool at_end() const { return p_ == end_; }

private:
    const char* p_;
    const char* end_;
};

template <class T>
struct tag {};

inline float get(Reader& r, tag<float>) { return r.raw<float>(); }
inline int get(Reader& r, tag<int>) { return r.raw<std::int32_t>(); }
inline std::size_t get(Reader& r, tag<std::size_t>) {
    const std::uint64_t v = r.raw<std::uint64_t>();
    if (v > SIZE_MAX) throw wire_error("an index does not fit");
    return static_cast<std::size_t>(v);
}
inline std::string get(Reader& r, tag<std::string>) {
    const auto n = r.raw<std::uint32_t>();
    if (n > max_string) throw wire_error("a string in the reply is too long");
    return r.bytes(n);
}
inline glm::vec2 get(Reader& r, tag<glm::vec2>) {
    const float x = get(r, tag<float>{});
    return {x, get(r, tag<float>{})};
}
inline glm::vec3 get(Reader& r, tag<glm::vec3>) {
    const float x = get(r, tag<float>{});
    const float y = get(r, tag<float>{});
    return {x, y, get(r, tag<float>{})};
}
inline Ray get(Reader& r, tag<Ray>) {
    const glm::vec3 o = get(r, tag<glm::vec3>{});
    return {o, get(r, tag<glm::vec3>{})};
}
inline Sphere get(Reader& r, tag<Sphere>) {
    const glm::vec3 c = get(r, tag<glm::vec3>{});
    return {c, get(r, tag<float>{})};
}
inline Rect get(Reader& r, tag<Rect>) {
    Rect x{};
    x.axis = get(r, tag<int>{});
    x.offset = get(r, tag<float>{});
    x.lo = get(r, tag<glm::vec2>{});
    x.hi = get(r, tag<glm::vec2>{});
    return x;
}
inline Roots get(Reader& r, tag<Roots>) {
    Roots x;
    x.count = get(r, tag<int>{});
    x.t[0] = get(r, tag<float>{});
    x.t[1] = get(r, tag<float>{});
    return x;
}
inline Hit get(Reader& r, tag<Hit>) {
    Hit h{};
    h.t = get(r, tag<float>{});
    h.index = get(r, tag<std::size_t>{});
    return h;
}
inline Object get(Reader& r, tag<Object>) {
    Object o;
    o.name = get(r, tag<std::string>{});
    o.shape = get(r, tag<Rect>{});
    o.color = get(r, tag<glm::vec3>{});
    return o;
}
inline Camera get(Reader& r, tag<Camera>) {
    Camera c{};
    c.eye = get(r, tag<glm::vec3>{});
    c.forward = get(r, tag<glm::vec3>{});
    c.up = get(r, tag<glm::vec3>{});
    c.focal_length = get(r, tag<float>{});
    c.film_height = get(r, tag<float>{});
    c.width = get(r, tag<int>{});
    c.height = get(r, tag<int>{});
    return c;
}
template <class T>
std::vector<T> get(Reader& r, tag<std::vector<T>>) {
    const auto n = r.raw<std::uint32_t>();
    if (n > max_items) throw wire_error("a list in the reply is too long");
    std::vector<T> items;
    items.reserve(n);
    for (std::uint32_t i = 0; i < n; ++i) items.push_back(get(r, tag<T>{}));
    return items;
}
inline Scene get(Reader& r, tag<Scene>) { return Scene{get(r, tag<std::vector<Object>>{})}; }
inline Canvas get(Reader& r, tag<Canvas>) {
    const int w = get(r, tag<int>{});
    const int h = get(r, tag<int>{});
    // A canvas the student built is valid by construction; one that is not came
    // from a broken reply. Canvas's constructor checks the size before allocating.
    if (w < 1 || h < 1 || static_cast<long long>(w) * h > Canvas::max_pixels)
        throw wire_error("the canvas in the reply has an impossible size");
    Canvas c(w, h);
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) c.at(i, j) = get(r, tag<glm::vec3>{});
    return c;
}
template <class T>
std::optional<T> get(Reader& r, tag<std::optional<T>>) {
    const auto has = r.raw<std::uint8_t>();
    if (has > 1) throw wire_error("an optional in the reply is neither empty nor full");
    if (!has) return std::nullopt;
    return get(r, tag<T>{});
}

template <class T>
std::decay_t<T> get(Reader& r) {
    return get(r, tag<std::decay_t<T>>{});
}

// ---- text, for a report that names the call that crashed ----------------------

inline std::string text(float x) { return float_text(x); }
inline std::string text(int v) { return std::to_string(v); }
inline std::string text(const std::string& s) { return "\"" + s + "\""; }
inline std::string text(const glm::vec2& v) { return "(" + text(v.x) + ", " + text(v.y) + ")"; }
inline std::string text(const glm::vec3& v) {
    return "(" + text(v.x) + ", " + text(v.y) + ", " + text(v.z) + ")";
}
inline std::string text(const Ray& r) { return "ray{origin " + text(r.origin) + ", direction " + text(r.direction) + "}"; }
inline std::string text(const Sphere& s) { return "sphere{centre " + text(s.center) + ", radius " + text(s.radius) + "}"; }
inline std::string text(const Rect& r) {
    return "rect{axis " + text(r.axis) + ", offset " + text(r.offset) + ", lo " + text(r.lo) + ", hi " + text(r.hi) + "}";
}
inline std::string text(const Camera& c) {
    return "camera{eye " + text(c.eye) + ", forward " + text(c.forward) + ", up " + text(c.up) + ", focal length " +
           text(c.focal_length) + ", film height " + text(c.film_height) + ", " + text(c.width) + " x " +
           text(c.height) + " pixels}";
}
inline std::string text(const Scene& s) {
    std::string out = "scene{";
    for (std::size_t i = 0; i < s.objects.size(); ++i) out += (i ? ", " : "") + s.objects[i].name;
    return out + "}";
}

inline std::string args_text() { return ""; }
template <class A, class... More>
std::string args_text(const A& a, const More&... more) {
    std::string rest = args_text(more...);
    return text(a) + (rest.empty() ? "" : ", " + rest);
}

}  // namespace raykit::wire
