// The exact answers the suites compare with (the ★ tier and step 03's check
// against step 02), behind one small interface.
//
// Why a table: a student's handout must not carry code that computes what a
// step asks for, and the exact roots of a ray and a sphere are exactly that.
// So the answers are precomputed. Each step whose suites ask for them has a
// generated data file, tests/NN_topic/exact_answers.cpp, that lists every
// (input -> exact answer) its cases ask for, keyed by the bit patterns of the
// float inputs (the inputs a case computes, e.g. through glm::normalize, are
// the keys, so no rounding of a printed decimal can shift a key).
//
// Two builds of the same interface:
//  - the instructor's copy has tests/support/reference_roots.hpp (113-bit
//    exact roots). There the answer is computed, compared with the table (a
//    missing or different entry fails the case: the committed data is stale)
//    and, when RAYKIT_EXACT_RECORD names a file, appended to it: this is how
//    `./kit exact --refresh` regenerates the data files;
//  - a handout has no reference_roots.hpp: the answer is only looked up.
//    A missing entry fails the case with a message saying the data is older
//    than the case; it never falls back to computing.
#pragma once

#include <doctest/doctest.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <string>

#include "raykit/ray.hpp"
#include "raykit/roots.hpp"
#include "raykit/sphere.hpp"

#if __has_include("reference_roots.hpp")
#include "reference_roots.hpp"
#define RAYKIT_EXACT_COMPUTED 1
#endif

namespace raykit::exact {

/// One recorded sphere_roots answer: key = origin, direction, centre, radius
/// (10 float bit patterns); the exact roots rounded to float.
struct RootsEntry {
    std::uint32_t key[10];
    int count;
    std::uint32_t t[2];
};

/// One recorded hit: key = the roots' key, then tmin and tmax; hit is 0 or 1.
struct HitEntry {
    std::uint32_t key[12];
    int hit;
    std::uint32_t t;
};

/// A step's data, defined in its generated tests/NN_topic/exact_answers.cpp.
struct Table {
    const RootsEntry* roots;
    std::size_t roots_size;
    const HitEntry* hits;
    std::size_t hits_size;
    const char* file;  // where it lives, for the message when an entry is missing
};

extern const Table table;

inline std::uint32_t bits(float x) {
    std::uint32_t u;
    std::memcpy(&u, &x, sizeof u);
    return u;
}

inline float from_bits(std::uint32_t u) {
    float x;
    std::memcpy(&x, &u, sizeof x);
    return x;
}

/// The key of a ray and a sphere; `extra` more floats follow when given.
struct Key {
    std::uint32_t k[12] = {};
    int size = 0;
    void add(float x) { k[size++] = bits(x); }
};

inline Key key_of(const Ray& ray, const Sphere& sphere) {
    Key key;
    for (int i = 0; i < 3; ++i) key.add(ray.origin[i]);
    for (int i = 0; i < 3; ++i) key.add(ray.direction[i]);
    for (int i = 0; i < 3; ++i) key.add(sphere.center[i]);
    key.add(sphere.radius);
    return key;
}

inline std::string hex(const Key& key) {
    std::string s;
    char buf[16];
    for (int i = 0; i < key.size; ++i) {
        std::snprintf(buf, sizeof buf, "%s0x%08x", i ? ", " : "", static_cast<unsigned>(key.k[i]));
        s += buf;
    }
    return s;
}

inline void missing(const char* what, const Key& key, bool differs = false) {
    FAIL_CHECK((differs ? "The precomputed exact " : "No precomputed exact ")
               << what << (differs ? " differs from the computed one" : "") << " for this input in " << table.file
               << ": the kit's data is older than this case (key " << hex(key)
               << "). Instructors: ./kit exact --refresh, then commit the file.");
}

inline const RootsEntry* find_roots(const Key& key) {
    for (std::size_t i = 0; i < table.roots_size; ++i)
        if (std::memcmp(table.roots[i].key, key.k, sizeof table.roots[i].key) == 0) return &table.roots[i];
    return nullptr;
}

inline const HitEntry* find_hit(const Key& key) {
    for (std::size_t i = 0; i < table.hits_size; ++i)
        if (std::memcmp(table.hits[i].key, key.k, sizeof table.hits[i].key) == 0) return &table.hits[i];
    return nullptr;
}

inline Roots roots_of(const RootsEntry& e) {
    Roots r;
    r.count = e.count;
    r.t[0] = from_bits(e.t[0]);
    r.t[1] = from_bits(e.t[1]);
    return r;
}

#if defined(RAYKIT_EXACT_COMPUTED)
/// Appends one line to the file RAYKIT_EXACT_RECORD names (if it does).
inline void record(const std::string& line) {
    static std::FILE* out = [] {
        const char* path = std::getenv("RAYKIT_EXACT_RECORD");
        return path ? std::fopen(path, "a") : nullptr;
    }();
    if (out == nullptr) return;
    std::fputs(line.c_str(), out);
    std::fputc('\n', out);
    std::fflush(out);
}

// Bit-for-bit equality: the table must hold exactly what is computed.
inline bool same(const Roots& a, const RootsEntry& e) {
    return a.count == e.count && bits(a.t[0]) == e.t[0] && bits(a.t[1]) == e.t[1];
}
#endif

/// The roots of |o + t d - c|^2 = r^2 for these float inputs, exact and
/// rounded to float (the contract of raykit::Roots), or nothing after a
/// failed check when the data has no entry for them.
inline std::optional<Roots> sphere_roots(const Ray& ray, const Sphere& sphere) {
    const Key key = key_of(ray, sphere);
    const RootsEntry* entry = find_roots(key);
#if defined(RAYKIT_EXACT_COMPUTED)
    const Roots r = reference::sphere_roots_rounded(ray, sphere);
    char buf[64];
    std::snprintf(buf, sizeof buf, " %d 0x%08x 0x%08x", r.count, static_cast<unsigned>(bits(r.t[0])),
                  static_cast<unsigned>(bits(r.t[1])));
    record("roots " + hex(key) + buf);
    if (entry == nullptr || !same(r, *entry)) {
        missing("roots", key, entry != nullptr);
        return std::nullopt;
    }
#endif
    if (entry == nullptr) {
        missing("roots", key);
        return std::nullopt;
    }
    return roots_of(*entry);
}

/// An exact answer that may be a miss: `known` is false after a failed check
/// when the data has no entry.
struct ExactHit {
    bool known = false;
    std::optional<float> t;
};

/// The closest exact root inside the closed window [tmin, tmax], rounded to float.
inline ExactHit sphere_hit(const Ray& ray, const Sphere& sphere, float tmin, float tmax) {
    Key key = key_of(ray, sphere);
    key.add(tmin);
    key.add(tmax);
    const HitEntry* entry = find_hit(key);
#if defined(RAYKIT_EXACT_COMPUTED)
    std::optional<float> hit;
    const Roots r = reference::sphere_roots_rounded(ray, sphere);
    for (int i = 0; i < r.count && !hit; ++i)
        if (tmin <= r.t[i] && r.t[i] <= tmax) hit = r.t[i];
    char buf[64];
    std::snprintf(buf, sizeof buf, " %d 0x%08x", hit ? 1 : 0, static_cast<unsigned>(hit ? bits(*hit) : 0u));
    record("hit " + hex(key) + buf);
    if (entry == nullptr || entry->hit != (hit ? 1 : 0) || (hit && entry->t != bits(*hit))) {
        missing("hit", key, entry != nullptr);
        return {};
    }
#endif
    if (entry == nullptr) {
        missing("hit", key);
        return {};
    }
    ExactHit out;
    out.known = true;
    if (entry->hit) out.t = from_bits(entry->t);
    return out;
}

}  // namespace raykit::exact
