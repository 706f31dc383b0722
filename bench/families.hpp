// The rays the benchmark shoots: families of rays with one sphere each, and
// families of rays into the Cornell box. Every family has its own fixed seed,
// so two runs see the same rays bit for bit.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "vec.hpp"

namespace raykit::bench {

struct SphereFamily {
    std::string id;           ///< short name, used in the CSV ("far_1e4")
    std::string label;        ///< for people ("far, 1e4 radii")
    std::string description;  ///< one sentence: what the rays are
    bool hard = false;        ///< one of the families where precision is at stake
    std::vector<Sample<float>> samples;  ///< all with the family's one sphere
};

struct BoxFamily {
    std::string id, label, description;
    std::vector<Vec3<float>> origins, directions;
};

/// The sphere families, `n` rays each: typical, far (1e3, 1e4, 3e4 radii),
/// tiny, huge, off-centre, grazing, inside.
std::vector<SphereFamily> sphere_families(std::size_t n);

/// Rays into the Cornell box: from the usual camera, and from inside (bounces).
std::vector<BoxFamily> box_families(std::size_t n);

}  // namespace raykit::bench
