// The benchmark's ray families. See families.hpp.
//
// Geometry is made in double and then rounded to float: the float values are
// the inputs every variant and the float128 yardstick share. The aim (how close
// to the centre a ray passes) is therefore approximate; the exact classification
// is computed later from the rounded inputs.

#include "families.hpp"

#include <cmath>
#include <cstdint>
#include <random>

namespace raykit::bench {

namespace {

constexpr double kPi = 3.14159265358979323846;

/// Uniform numbers from a fixed seed. std::mt19937_64's output is fixed by the
/// standard; the distributions of <random> are not, so the conversion to
/// [0, 1) is done here.
class Rng {
public:
    explicit Rng(std::uint64_t seed) : engine_(seed) {}
    double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
    double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
    /// Uniform on the unit sphere (Marsaglia-free: z uniform, angle uniform).
    Vec3<double> direction() {
        const double z = uniform(-1, 1), phi = uniform(0, 2 * kPi);
        const double s = std::sqrt(1 - z * z);
        return {s * std::cos(phi), s * std::sin(phi), z};
    }
    /// A unit vector perpendicular to u.
    Vec3<double> perpendicular(const Vec3<double>& u) {
        for (;;) {
            const Vec3<double> v = direction();
            const Vec3<double> p = v - dot(v, u) * u;
            const double len = std::sqrt(dot(p, p));
            if (len > 0.1) return (1 / len) * p;
        }
    }
    /// A direction length in [1/2, 2]: the kit's rays need not be unit length.
    double length() { return std::exp2(uniform(-1, 1)); }

private:
    std::mt19937_64 engine_;
};

Vec3<double> normalized(const Vec3<double>& v) { return (1 / std::sqrt(dot(v, v))) * v; }

Vec3<float> to_float(const Vec3<double>& v) {
    return {static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)};
}

Sample<float> make_sample(const Vec3<double>& o, const Vec3<double>& d, const Vec3<double>& c, double r) {
    return {to_float(o), to_float(d), to_float(c), static_cast<float>(r)};
}

/// A ray from distance `dist` (in radii) of the centre, passing the centre at
/// `impact` radii, with a random direction length.
Sample<float> aimed(Rng& rng, const Vec3<double>& c, double r, double dist, double impact) {
    const Vec3<double> u = rng.direction();
    const Vec3<double> o = c + (dist * r) * u;
    const Vec3<double> target = c + (impact * r) * rng.perpendicular(u);
    const Vec3<double> d = rng.length() * normalized(target - o);
    return make_sample(o, d, c, r);
}

/// Impact parameters spread uniformly over a disc 1.25 radii wide: about two
/// rays in three hit.
double disc_impact(Rng& rng) { return 1.25 * std::sqrt(rng.uniform()); }

}  // namespace

std::vector<SphereFamily> sphere_families(std::size_t n) {
    std::vector<SphereFamily> out;
    std::uint64_t seed = 20240501;
    double band = kTangentBand;  // the families below the pbrt ones use the wider band
    auto add = [&](const char* id, const char* label, const char* what, bool hard, auto&& make) {
        SphereFamily f{id, label, what, hard, band, {}};
        Rng rng(seed++);
        f.samples.reserve(n);
        for (std::size_t i = 0; i < n; ++i) f.samples.push_back(make(rng));
        out.push_back(std::move(f));
    };
    const Vec3<double> near_origin{0.7, -0.4, 1.3};

    add("typical", "typical", "unit sphere 2 to 10 radii away, two rays in three hit", false,
        [&](Rng& rng) { return aimed(rng, near_origin, 1.0, rng.uniform(2, 10), disc_impact(rng)); });
    struct Far { double k; const char* id; const char* label; };
    for (const Far far : {Far{1e3, "far_1e3", "far, 1e3 radii"}, Far{1e4, "far_1e4", "far, 1e4 radii"},
                          Far{3e4, "far_3e4", "far, 3e4 radii"}}) {
        add(far.id, far.label, "unit sphere k radii away (k +- 10%), two rays in three hit", true,
            [&](Rng& rng) { return aimed(rng, near_origin, 1.0, far.k * rng.uniform(0.9, 1.1), disc_impact(rng)); });
    }
    add("tiny", "tiny, r = 1e-3", "sphere of radius 1e-3 about 3 units away, rays from near the world origin",
        true, [&](Rng& rng) {
            const Vec3<double> c{1.7, 0.4, -2.3};
            const double r = 1e-3;
            const Vec3<double> o{rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5)};
            const Vec3<double> to_c = normalized(c - o);
            const Vec3<double> target = c + (disc_impact(rng) * r) * rng.perpendicular(to_c);
            return make_sample(o, rng.length() * normalized(target - o), c, r);
        });
    add("huge", "huge, r = 1e4", "ground sphere of radius 1e4, camera 0.1 to 10 units above it, looking down to level",
        true, [&](Rng& rng) {
            const double r = 1e4;
            const Vec3<double> c{3.7, -r, -2.1};
            const double height = std::exp2(rng.uniform(std::log2(0.1), std::log2(10.0)));
            const Vec3<double> o{rng.uniform(-20, 20), height, rng.uniform(-20, 20)};
            const double elevation = rng.uniform(-1.4, 0.09), azimuth = rng.uniform(0, 2 * kPi);
            const Vec3<double> d{std::cos(elevation) * std::cos(azimuth), std::sin(elevation),
                                 std::cos(elevation) * std::sin(azimuth)};
            return make_sample(o, rng.length() * d, c, r);
        });
    add("off_centre", "off-centre", "unit sphere 1e4 units from the world origin, rays from 2 to 10 radii",
        true, [&](Rng& rng) {
            const Vec3<double> far_away{8192.6, -5120.3, 6143.9};
            return aimed(rng, far_away, 1.0, rng.uniform(2, 10), disc_impact(rng));
        });
    add("grazing", "grazing", "impact parameter within 1e-3 of the radius, 2 to 10 radii away", true,
        [&](Rng& rng) {
            return aimed(rng, near_origin, 1.0, rng.uniform(2, 10), 1.0 + rng.uniform(-1e-3, 1e-3));
        });
    add("inside", "origin inside", "origin anywhere inside the unit sphere, any direction", false,
        [&](Rng& rng) {
            const double radius = 0.999 * std::cbrt(rng.uniform());
            const Vec3<double> o = near_origin + radius * rng.direction();
            return make_sample(o, rng.length() * rng.direction(), near_origin, 1.0);
        });

    // The ranges of pbrt-v4's own sphere tests (src/pbrt/shapes_test.cpp): a
    // sphere at the world origin of radius 10^U(-4, 4), origin coordinates
    // +-10^U(-e, e), the ray aimed at a random point of the sphere's bounding
    // box, half the directions normalised. |f| / r reaches 10^(e + 4): the
    // scale at which h^2 - a c cancels beyond what even double holds.
    band = kNarrowTangentBand;
    struct Pbrt { double e; const char* id; const char* label; };
    for (const Pbrt p : {Pbrt{4, "pbrt_e4", "pbrt ranges, e = 4"}, Pbrt{6, "pbrt_e6", "pbrt ranges, e = 6"},
                         Pbrt{8, "pbrt_e8", "pbrt ranges, e = 8"}}) {
        add(p.id, p.label, "pbrt-v4's sphere test: radius 10^U(-4,4), origin coordinates +-10^U(-e,e), aimed into "
            "the bounding box", true, [&](Rng& rng) {
                auto signed_exp = [&](double e) {
                    return (rng.uniform() < 0.5 ? -1.0 : 1.0) * std::pow(10.0, rng.uniform(-e, e));
                };
                const double r = std::pow(10.0, rng.uniform(-4, 4));
                const Vec3<double> o{signed_exp(p.e), signed_exp(p.e), signed_exp(p.e)};
                const Vec3<double> target{rng.uniform(-r, r), rng.uniform(-r, r), rng.uniform(-r, r)};
                Vec3<double> d = target - o;
                if (rng.uniform() < 0.5) d = normalized(d);
                return make_sample(o, d, {0, 0, 0}, r);
            });
    }

    // The ground: a sphere centred below the camera, the camera 1 to 2 units
    // above its top, looking 1e-4 to 0.3 rad below the horizontal (log-uniform):
    // the horizon dips by sqrt(2 H / r), so many rays are near-tangent misses.
    struct Ground { double r; const char* id; const char* label; const char* what; };
    for (const Ground g : {Ground{1e3, "ground_1e3", "ground, r = 1e3", "sphere of radius 1e3 below the camera"},
                           Ground{6.4e6, "ground_earth", "ground, the Earth",
                                  "sphere of radius 6.4e6 (the Earth in metres) below the camera"}}) {
        const std::string what = std::string(g.what) + ", 1 to 2 units above it, looking 1e-4 to 0.3 rad down";
        add(g.id, g.label, what.c_str(), true, [&](Rng& rng) {
            const Vec3<double> c{0, -g.r, 0};
            const Vec3<double> o{rng.uniform(-1, 1), rng.uniform(1, 2), rng.uniform(-1, 1)};
            const double down = std::pow(10.0, rng.uniform(-4, std::log10(0.3)));
            const double azimuth = rng.uniform(0, 2 * kPi);
            const Vec3<double> d{std::cos(down) * std::cos(azimuth), -std::sin(down),
                                 std::cos(down) * std::sin(azimuth)};
            return make_sample(o, rng.length() * d, c, g.r);
        });
    }
    return out;
}

std::vector<BoxFamily> box_families(std::size_t n) {
    std::vector<BoxFamily> out;
    {
        // A camera beside the Cornell box's own (the data's eye is (278, 273, -800); this family's
        // has y = 278, as when it was first measured): through the box's open side, aimed at a
        // square a little wider than the opening, so some miss.
        BoxFamily f{"box_camera", "box, camera rays", "from (278, 278, -800) through the open side", {}, {}};
        Rng rng(777001);
        const Vec3<double> eye{278, 278, -800};
        for (std::size_t i = 0; i < n; ++i) {
            const Vec3<double> target{rng.uniform(-22, 578), rng.uniform(-22, 578), 0};
            f.origins.push_back(to_float(eye));
            f.directions.push_back(to_float(normalized(target - eye)));
        }
        out.push_back(std::move(f));
    }
    {
        BoxFamily f{"box_bounce", "box, bounce rays", "from anywhere inside the box, any direction", {}, {}};
        Rng rng(777002);
        for (std::size_t i = 0; i < n; ++i) {
            f.origins.push_back(to_float(Vec3<double>{rng.uniform(1, 554), rng.uniform(1, 554), rng.uniform(1, 554)}));
            f.directions.push_back(to_float(rng.direction()));
        }
        out.push_back(std::move(f));
    }
    return out;
}

}  // namespace raykit::bench
