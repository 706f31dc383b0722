// The exact answers the suites compare with (the ★ tier and step 03's check
// against step 02), behind one small interface.
//
// Why a table: a student's handout must not carry code that computes what a
// step asks for, and the exact roots of a ray and a sphere are exactly that.
// So the answers are precomputed. Each step whose suites ask for them has a
// generated data file, tests/NN_topic/exact_answers.cpp, that lists every
// (input -> exact answer) its cases ask for, keyed by the bit patterns of the
// float inputs. A case looks its inputs up and then runs on the recorded ones
// (see snap_ulps: another compiler may compute a case's input an ulp away).
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
#include "ulps.hpp"

#if __has_include("reference_roots.hpp")
#include "reference_roots.hpp"
#define RAYKIT_EXACT_COMPUTED 1
#endif

namespace raykit::exact {

/// A recorded Roots value: count and the two roots' bit patterns.
struct RecordedRoots {
    int count;
    std::uint32_t t[2];
};

/// One recorded sphere_roots answer: key = origin, direction, centre, radius
/// (10 float bit patterns); the exact roots rounded to float; then what the
/// usual wrong formulas give on the same inputs (the suspects of a failure:
/// a = 1, c' in float, the textbook formula and the shortcut in float, the textbook formula in double;
/// reference_roots.hpp).
struct RootsEntry {
    std::uint32_t key[10];
    int count;
    std::uint32_t t[2];
    RecordedRoots suspects[5];
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

/// How far apart two keys are: the largest distance, in ulps, of one float
/// from its counterpart (the largest int64 when a NaN is met).
inline std::int64_t key_distance(const std::uint32_t* a, const std::uint32_t* b, int n) {
    std::int64_t worst = 0;
    for (int i = 0; i < n; ++i) {
        const std::int64_t d = grading::ulp_distance(from_bits(a[i]), from_bits(b[i]));
        if (d > worst) worst = d;
    }
    return worst;
}

/// How far a case's inputs may be from the recorded ones and still be the
/// same case. The inputs are computed by the test code (glm::normalize and
/// the like), and compilers round them differently by an ulp or two: Clang
/// contracts a * b + c into a fused multiply-add (even when folding constants
/// on a machine without one), GCC in ISO mode does not. Such a case takes the
/// nearest recorded inputs, and the student's function and the exact answer
/// both use them: whichever entry it snaps to, input and answer agree.
constexpr std::int64_t snap_ulps = 16;

/// The entry whose key is `key`, else the nearest within snap_ulps of it.
template <class Entry>
const Entry* find_entry(const Entry* entries, std::size_t size, const Key& key) {
    const Entry* best = nullptr;
    std::int64_t best_distance = snap_ulps + 1;
    for (std::size_t i = 0; i < size; ++i) {
        if (std::memcmp(entries[i].key, key.k, sizeof entries[i].key) == 0) return &entries[i];
        const std::int64_t d = key_distance(entries[i].key, key.k, key.size);
        if (d < best_distance) {
            best = &entries[i];
            best_distance = d;
        }
    }
    return best;
}

inline void missing(const char* what, const Key& key, const char* problem) {
    const std::string message = std::string("The exact ") + what + " for this input in " + table.file + " " +
                                problem + ": the kit's data is older than this case (key " + hex(key) +
                                "). Instructors: ./kit exact --refresh, then commit the file.";
    FAIL_CHECK(message);
}

inline const char* why_missing(const void* entry) {
    return entry != nullptr ? "differs from the one computed now" : "is missing";
}

inline Ray ray_of(const std::uint32_t* k) {
    return Ray{{from_bits(k[0]), from_bits(k[1]), from_bits(k[2])}, {from_bits(k[3]), from_bits(k[4]), from_bits(k[5])}};
}

inline Sphere sphere_of(const std::uint32_t* k) {
    return Sphere{{from_bits(k[6]), from_bits(k[7]), from_bits(k[8])}, from_bits(k[9])};
}

inline Roots roots_of(int count, const std::uint32_t* t) {
    Roots r;
    r.count = count;
    r.t[0] = from_bits(t[0]);
    r.t[1] = from_bits(t[1]);
    return r;
}

inline Roots roots_of(const RootsEntry& e) { return roots_of(e.count, e.t); }

/// What the usual wrong formulas give on a case's inputs, for naming the cause of a failure
/// (grading::measured_cause): the exact roots of the formula that takes a = d.d as 1; the exact
/// formula with only f and c' = f.f - r^2 computed in float; the textbook formula in float; the
/// unit-direction shortcut -h -+ sqrt(h^2 - c') in float; the textbook formula in double.
struct Suspects {
    Roots a_one, float_cprime, textbook_float, shortcut_float, textbook_double;
};

inline Suspects suspects_of(const RootsEntry& e) {
    return {roots_of(e.suspects[0].count, e.suspects[0].t), roots_of(e.suspects[1].count, e.suspects[1].t),
            roots_of(e.suspects[2].count, e.suspects[2].t), roots_of(e.suspects[3].count, e.suspects[3].t),
            roots_of(e.suspects[4].count, e.suspects[4].t)};
}

inline std::string recorded_text(const Roots& r) {
    char buf[64];
    std::snprintf(buf, sizeof buf, " %d 0x%08x 0x%08x", r.count, static_cast<unsigned>(bits(r.t[0])),
                  static_cast<unsigned>(bits(r.t[1])));
    return buf;
}

inline bool same_roots(const Roots& r, const RecordedRoots& e) {
    return r.count == e.count && bits(r.t[0]) == e.t[0] && bits(r.t[1]) == e.t[1];
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

/// Records one roots entry: the inputs' key, the exact roots and the suspects' (./kit exact --refresh).
inline void record_roots(const Ray& ray, const Sphere& sphere, const Roots& r, const reference::SuspectRoots& m) {
    record("roots " + hex(key_of(ray, sphere)) + recorded_text(r) + recorded_text(m.a_one) +
           recorded_text(m.float_cprime) + recorded_text(m.textbook_float) + recorded_text(m.shortcut_float) +
           recorded_text(m.textbook_double));
}
#endif

/// A case's inputs as recorded (equal to the ones asked for, or within
/// snap_ulps of them), and their exact roots rounded to float.
struct SphereCase {
    Ray ray;
    Sphere sphere;
    Roots roots;
    Suspects suspects;
};

/// The roots of |o + t d - c|^2 = r^2 for these float inputs, exact and
/// rounded to float (the contract of raykit::Roots), or nothing after a
/// failed check when the data has no entry for them. Call the function
/// under test with the returned case's ray and sphere.
inline std::optional<SphereCase> sphere_roots(const Ray& ray, const Sphere& sphere) {
    const Key key = key_of(ray, sphere);
    const RootsEntry* entry = find_entry(table.roots, table.roots_size, key);
#if defined(RAYKIT_EXACT_COMPUTED)
    // Computed on the recorded inputs when there are some (so that the data
    // does not change with the compiler that regenerates it), else on these.
    const Ray r_in = entry ? ray_of(entry->key) : ray;
    const Sphere s_in = entry ? sphere_of(entry->key) : sphere;
    const Roots r = reference::sphere_roots_rounded(r_in, s_in);
    const reference::SuspectRoots m = reference::suspect_roots(r_in, s_in);
    record_roots(r_in, s_in, r, m);
    const bool same = entry && same_roots(r, RecordedRoots{entry->count, {entry->t[0], entry->t[1]}}) &&
                      same_roots(m.a_one, entry->suspects[0]) &&
                      same_roots(m.float_cprime, entry->suspects[1]) && same_roots(m.textbook_float, entry->suspects[2]) &&
                      same_roots(m.shortcut_float, entry->suspects[3]) &&
                      same_roots(m.textbook_double, entry->suspects[4]);
    if (!same) {
        missing("roots", key, why_missing(entry));
        return std::nullopt;
    }
#endif
    if (entry == nullptr) {
        missing("roots", key, why_missing(entry));
        return std::nullopt;
    }
    return SphereCase{ray_of(entry->key), sphere_of(entry->key), roots_of(*entry), suspects_of(*entry)};
}

/// A hit case's inputs as recorded, and the closest exact root inside the
/// closed window [tmin, tmax] rounded to float.
struct HitCase {
    Ray ray;
    Sphere sphere;
    float tmin, tmax;
    std::optional<float> t;
    std::optional<Suspects> suspects;  // the suspects of the same ray and sphere, when recorded
};

/// The exact closest hit for these inputs, or nothing after a failed check
/// when the data has no entry for them. Call the function under test with
/// the returned case's inputs.
inline std::optional<HitCase> sphere_hit(const Ray& ray, const Sphere& sphere, float tmin, float tmax) {
    Key key = key_of(ray, sphere);
    key.add(tmin);
    key.add(tmax);
    const HitEntry* entry = find_entry(table.hits, table.hits_size, key);
#if defined(RAYKIT_EXACT_COMPUTED)
    const Ray r_in = entry ? ray_of(entry->key) : ray;
    const Sphere s_in = entry ? sphere_of(entry->key) : sphere;
    const float lo = entry ? from_bits(entry->key[10]) : tmin, hi = entry ? from_bits(entry->key[11]) : tmax;
    std::optional<float> hit;
    const Roots r = reference::sphere_roots_rounded(r_in, s_in);
    for (int i = 0; i < r.count && !hit; ++i)
        if (lo <= r.t[i] && r.t[i] <= hi) hit = r.t[i];
    Key in = key_of(r_in, s_in);
    in.add(lo);
    in.add(hi);
    char buf[64];
    std::snprintf(buf, sizeof buf, " %d 0x%08x", hit ? 1 : 0, static_cast<unsigned>(hit ? bits(*hit) : 0u));
    record("hit " + hex(in) + buf);
    // The roots of the same ray and sphere with their suspects, so that a failed hit's cause can be
    // measured too (grading::check_hit_case).
    record_roots(r_in, s_in, r, reference::suspect_roots(r_in, s_in));
    const bool same = entry && entry->hit == (hit ? 1 : 0) && (!hit || entry->t == bits(*hit));
    if (!same) {
        missing("hit", key, why_missing(entry));
        return std::nullopt;
    }
#endif
    if (entry == nullptr) {
        missing("hit", key, why_missing(entry));
        return std::nullopt;
    }
    HitCase out{ray_of(entry->key), sphere_of(entry->key), from_bits(entry->key[10]), from_bits(entry->key[11]), {}, {}};
    if (entry->hit) out.t = from_bits(entry->t);
    if (const RootsEntry* roots = find_entry(table.roots, table.roots_size, key_of(out.ray, out.sphere)))
        out.suspects = suspects_of(*roots);
    return out;
}

}  // namespace raykit::exact
