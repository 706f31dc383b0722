// Hidden cases of step 01 (see hidden.hpp): the unit sphere at the origin.

#include "hidden.hpp"
#include "raykit/unit_sphere.hpp"
#include "rules.hpp"

using namespace raykit;
using namespace raykit::hidden;

namespace {

const glm::vec3 sphere_centre{0, 0, 0};   // the unit sphere's

// Each family makes a ray; the reference says what the answer is.
template <class MakeRay>
void roots_family(const char* family, MakeRay make, const char* why) {
    Draw draw(family);
    for (int i = 0; i < draws; ++i) {
        const Ray ray = make(draw);
        const Roots expected = remote::reference<Roots>("unit_sphere_roots", ray);
        const Roots got = unit_sphere_roots(ray);
        if (!agree(expected, got)) {
            grading::check_roots("unit_sphere_roots(ray)", input_note(i, grading::show(ray)), expected, got, why);
            return;
        }
    }
}

template <class MakeCall>
void window_family(const char* family, MakeCall make, const char* why) {
    Draw draw(family);
    for (int i = 0; i < draws; ++i) {
        float tmin = 0, tmax = 0;
        const Ray ray = make(draw, tmin, tmax);
        const auto expected = remote::reference<std::optional<float>>("intersect_unit_sphere", ray, tmin, tmax);
        const auto got = intersect_unit_sphere(ray, tmin, tmax);
        if (!agree(expected, got) &&
            !agree_in_window(expected, got, remote::reference<Roots>("unit_sphere_roots", ray),
                             [&] { return unit_sphere_roots(ray); }, tmin, tmax)) {
            // No probe of an own epsilon here (grading.hpp, own_epsilon): its rays are fixed, so a hidden
            // case that made those calls would show a submission inputs a visible case shows too, which the
            // integrity self-tests count as hidden inputs carried over. The visible cases name it.
            grading::check_hit("intersect_unit_sphere(ray, tmin, tmax)",
                               input_note(i, grading::show(ray) + ", window [" + grading::show(tmin) + ", " +
                                                 grading::show(tmax) + "]"),
                               expected, got, why);
            return;
        }
    }
}

// An axis-aligned ray along axis a from k units before the centre, at height y
// (0: through the centre, 1: tangent), its direction scaled by a power of two:
// every root is exact in float.
Ray axis_ray(Draw& d, float y) {
    const int a = d.integer(0, 2);
    const float s = d.sign();
    const float k = static_cast<float>(d.integer(2, 40)) * 0.5f;
    return {d.permute({-s * k, y * d.sign(), 0}, a), d.permute({s * d.power_of_two(-3, 3), 0, 0}, a)};
}

}  // namespace

TEST_SUITE_BEGIN("hidden");

TEST_CASE("unit_sphere_roots on random rays that pass through the sphere" *
          doctest::description("4. What the discriminant says")) {
    roots_family("01 through", [](Draw& d) {
        return aimed(d.around(sphere_centre, 1.5f, 10), d.around(sphere_centre, 0, 0.7f), d.uniform(0.1f, 8));
    }, "A random ray aimed well inside the sphere: two roots.");
}

TEST_CASE("unit_sphere_roots on random rays that miss the sphere" *
          doctest::description("4. What the discriminant says")) {
    roots_family("01 miss", [](Draw& d) {
        const glm::vec3 o = d.around(sphere_centre, 2, 10);
        // Aim at a point beside the sphere, perpendicular to the line of sight.
        const glm::vec3 side = glm::normalize(glm::cross(o, d.direction()));
        return aimed(o, d.uniform(1.3f, 3) * side, d.uniform(0.1f, 8));
    }, "A random ray that passes well outside the sphere: no roots.");
}

TEST_CASE("unit_sphere_roots from random origins inside the sphere and behind it" *
          doctest::description("4. What the discriminant says")) {
    roots_family("01 inside behind", [](Draw& d) {
        if (d.coin()) return Ray{d.around(sphere_centre, 0, 0.8f), d.uniform(0.1f, 8) * d.direction()};
        const glm::vec3 o = d.around(sphere_centre, 1.5f, 10);
        return aimed(o, 2.0f * o - d.around(sphere_centre, 0, 0.6f), d.uniform(0.1f, 8));  // pointing away
    }, "Roots behind the origin are roots too: this function knows nothing of windows.");
}

TEST_CASE("unit_sphere_roots on exact tangents and axis rays" *
          doctest::description("4. What the discriminant says")) {
    roots_family("01 tangent", [](Draw& d) { return axis_ray(d, d.coin() ? 1.0f : 0.0f); },
                 "An axis-aligned ray at height 1 touches the sphere once; at height 0 it goes through the centre.");
}

TEST_CASE("unit_sphere_roots from origins on the surface: tangent and heading in and out" *
          doctest::description("4. What the discriminant says")) {
    roots_family("01 surface", [](Draw& d) { return surface_ray(d, sphere_centre, 1, d.integer(0, 2), false); },
                 "The origin is on the sphere (c = 0): a direction perpendicular to o (h = 0) touches it once "
                 "at t = 0; any other has the roots 0 and -2h/a. Never a NaN root.");
}

TEST_CASE("intersect_unit_sphere from origins on the surface" *
          doctest::description("5. The closest root in a window")) {
    window_family("01 surface windows", [](Draw& d, float& tmin, float& tmax) {
        tmin = d.coin() ? 0.0f : -10.0f;
        tmax = std::numeric_limits<float>::infinity();
        return surface_ray(d, sphere_centre, 1, d.integer(0, 2), false);
    }, "The root t = 0 is inside a window from tmin <= 0: the ray starting on the sphere hits it there.");
}

TEST_CASE("unit_sphere_roots on degenerate input" * doctest::description("2. The ray meets the sphere")) {
    // The basic tier's degenerate input: a zero direction, from anywhere (NaN and
    // infinity are the ★ tier's: they are not drawn here).
    roots_family("01 degenerate", [](Draw& d) { return Ray{d.around(sphere_centre, 0, 5), {0, 0, 0}}; },
                 "With d = 0 there is no line to intersect: no roots.");
}

TEST_CASE("unit_sphere_roots on rays holding NaN or infinity or whose d.d overflows or underflows" *
          doctest::description("2. The ray meets the sphere")) {
    // The expected answer is the header's rule, count 0, not the reference's; where d.d overflows
    // or underflows float, count 0 or the true roots (those of the unit direction, scaled).
    Draw draw("01 contract");
    for (int i = 0; i < draws; ++i) {
        Ray ray = aimed(draw.around(sphere_centre, 1.5f, 10), draw.around(sphere_centre, 0, 0.7f), draw.uniform(0.1f, 8));
        const int k = spoil(draw, ray, nullptr, i % 3, true);
        const Roots got = unit_sphere_roots(ray);
        const Roots truth = k ? scaled_roots(remote::reference<Roots>("unit_sphere_roots", unscaled(ray, k)), k) : Roots{};
        if (k ? !agree_miss_or_true(truth, got) : !agree(Roots{}, got)) {
            grading::check_roots("unit_sphere_roots(ray)", input_note(i, grading::show(ray)), truth, got,
                                 k ? "A direction whose d.d overflows or underflows float may count as a miss, or "
                                     "give the true roots, computed in a wider type (unit_sphere.hpp); never NaN."
                                   : "A ray holding NaN or infinity counts as a miss (unit_sphere.hpp): count 0, "
                                     "never a NaN root.");
            return;
        }
    }
}

TEST_CASE("unit_sphere_roots on rays with tiny directions and subnormal components" *
          doctest::description("2. The ray meets the sphere")) {
    roots_family("01 tiny", [](Draw& d) { return tiny_ray(d, sphere_centre, 1); },
                 "A direction of length 1e-6 down to 1e-17 (some with a subnormal component) is a ray: d.d is "
                 "a normal float, and t counts steps of d, so the roots are large. Only d = 0 is no ray.");
}

TEST_CASE("intersect_unit_sphere with random windows" * doctest::description("5. The closest root in a window")) {
    window_family("01 windows", [](Draw& d, float& tmin, float& tmax) {
        const Ray ray = aimed(d.around(sphere_centre, 0, 10), d.around(sphere_centre, 0, 0.7f), d.uniform(0.1f, 8));
        const Roots r = remote::reference<Roots>("unit_sphere_roots", ray);
        // Window ends well away from the roots (a tenth of their gap), on either side.
        const float lo = r.count ? r.t[0] : -1, hi = r.count ? r.t[1] : 1, gap = 0.1f * (hi - lo) + 0.01f;
        const float cuts[] = {lo - 5 * gap, lo - gap, lo + gap, hi - gap, hi + gap, hi + 5 * gap};
        int a = d.integer(0, 5), b = d.integer(0, 5);
        if (a > b) std::swap(a, b);
        tmin = cuts[a];
        tmax = d.integer(0, 7) == 0 ? std::numeric_limits<float>::infinity() : cuts[b];
        return ray;
    }, "The smallest root inside the window, or no hit.");
}

TEST_CASE("intersect_unit_sphere with a root exactly at a window end" *
          doctest::description("5. The closest root in a window")) {
    window_family("01 window ends", [](Draw& d, float& tmin, float& tmax) {
        const Ray ray = axis_ray(d, 0);
        const Roots r = remote::reference<Roots>("unit_sphere_roots", ray);
        const float root = r.t[d.integer(0, 1)];
        if (d.coin()) {
            tmin = root;
            tmax = root + d.uniform(0, 4) * d.integer(0, 1);
        } else {
            tmin = root - d.uniform(0, 4);
            tmax = root;
        }
        return ray;
    }, "The window is closed: a root exactly at tmin or tmax counts.");
}

TEST_SUITE_END();
