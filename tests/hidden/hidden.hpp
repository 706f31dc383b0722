// Hidden cases: random inputs from the same families as the visible cases,
// judged against the reference solution by the visible tiers' rules.
//
// Why: the visible cases are in the handout, so a table of their inputs could
// pass them all. Hidden cases draw fresh inputs per submission (the seed is a
// hash of the student's files, printed in the report, so a regrade meets the same
// inputs) and ask the reference's answers program for the expected answer.
//
// Every family is built so that any correct float implementation agrees with the
// reference within the basic tier's tolerance (tests/support/grading.hpp, close):
// rays aimed well inside or well outside the silhouette, tangents and window
// ends only where the geometry is exact in float (integer coordinates, axis-
// aligned directions scaled by powers of two). The numerically hard rays stay in
// the ★ robust tier, which is optional.
//
// These files never ship in a handout (tools/kitlib/commands/handout.py).
#pragma once

#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <random>
#include <string>

#include <glm/geometric.hpp>

#include "../support/grading.hpp"
#include "../support/remote.hpp"

namespace raykit::hidden {

/// How many inputs one family draws: enough that a table of the visible inputs,
/// or an answer right only on special values, fails; few enough to stay quick.
constexpr int draws = 24;

inline std::uint64_t seed_for(const char* family) {
    const char* text = std::getenv("RAYKIT_SEED");
    std::uint64_t seed = text ? std::strtoull(text, nullptr, 16) : 0x5eedu;
    for (const char* p = family; *p; ++p) seed = (seed ^ static_cast<unsigned char>(*p)) * 0x100000001b3ull;
    return seed;
}

/// The random source of one family: seeded by the submission and the family's name.
class Draw {
public:
    explicit Draw(const char* family) : rng_(seed_for(family)) {}

    float uniform(float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(rng_); }
    int integer(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng_); }
    bool coin() { return integer(0, 1) == 1; }
    float sign() { return coin() ? 1.0f : -1.0f; }
    /// 2^k for k in [lo, hi]: scales a direction without rounding anything.
    float power_of_two(int lo, int hi) { return std::ldexp(1.0f, integer(lo, hi)); }

    /// A direction spread over the sphere (not unit length unless normalized).
    glm::vec3 direction() {
        for (;;) {
            const glm::vec3 v{uniform(-1, 1), uniform(-1, 1), uniform(-1, 1)};
            const float len2 = glm::dot(v, v);
            if (len2 > 0.05f && len2 <= 1) return v / std::sqrt(len2);
        }
    }
    /// A point at distance in [lo, hi] from `centre`.
    glm::vec3 around(const glm::vec3& centre, float lo, float hi) { return centre + uniform(lo, hi) * direction(); }

    /// Places an axis-aligned picture: v's components moved to axes (a, a+1, a+2).
    glm::vec3 permute(const glm::vec3& v, int a) {
        glm::vec3 out;
        for (int k = 0; k < 3; ++k) out[(k + a) % 3] = v[k];
        return out;
    }

private:
    std::mt19937_64 rng_;
};

/// The ray from `o` towards `target`, its direction of length `length`.
inline Ray aimed(const glm::vec3& o, const glm::vec3& target, float length) {
    return {o, length * glm::normalize(target - o)};
}

/// Reports one failed hidden draw with its input (the grader hides it from the
/// student before the due date and shows the family instead).
inline std::string input_note(int draw, const std::string& input) {
    return "draw " + std::to_string(draw + 1) + " of " + std::to_string(draws) + ": " + input;
}

}  // namespace raykit::hidden
