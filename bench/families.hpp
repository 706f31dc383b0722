// The rays the benchmark shoots: families of rays with one sphere each, and
// families of rays into the Cornell box. Every family has its own fixed seed,
// so two runs see the same rays bit for bit.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "vec.hpp"

namespace raykit::bench {

/// The near-tangent band, relative to the radius: rays whose line passes the
/// centre within it of the radius are not judged. Outside it a float
/// formulation that does its job classifies every ray correctly up to a few
/// thousand radii away (the error of the line's distance is about |f| 2^-24).
constexpr double kTangentBand = 1e-4;
/// The narrower band of the pbrt and ground families, where the point is to
/// judge what happens close to a tangent at every scale.
constexpr double kNarrowTangentBand = 1e-5;

struct SphereFamily {
    std::string id;           ///< short name, used in the CSV ("far_1e4")
    std::string label;        ///< for people ("far, 1e4 radii")
    std::string description;  ///< one sentence: what the rays are
    bool hard = false;        ///< one of the families where precision is at stake
    double tangent_band = 0;  ///< rays with |distance of the line / r - 1| within it are not judged
    std::vector<Sample<float>> samples;  ///< all with the family's one sphere
};

struct BoxFamily {
    std::string id, label, description;
    std::vector<Vec3<float>> origins, directions;
};

/// The sphere families, `n` rays each: typical, far (1e3, 1e4, 3e4 radii),
/// tiny, huge, off-centre, grazing, inside; pbrt-v4's test ranges (e = 4, 6,
/// 8) and the ground (radius 1e3 and the Earth's, seen from 1 to 2 units up).
std::vector<SphereFamily> sphere_families(std::size_t n);

/// Rays into the Cornell box: from a camera 5 mm above the data's eye, and from inside (bounces).
std::vector<BoxFamily> box_families(std::size_t n);

}  // namespace raykit::bench
