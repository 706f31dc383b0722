/// \file sphere.hpp
/// \brief A sphere given by its centre and radius.
#pragma once

#include <glm/vec3.hpp>

namespace raykit {

/// The sphere `|x - center|^2 = r^2`: the points `x` at distance `r` from `center`.
///
/// A radius that is zero, negative, NaN or infinite describes no sphere: the
/// reference solutions report no intersection for it.
struct Sphere {
    glm::vec3 center;  ///< The centre, in scene units.
    float radius;      ///< `r > 0`, in scene units.
};

}  // namespace raykit
