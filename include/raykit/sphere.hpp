/// \file sphere.hpp
/// \brief A sphere given by its centre and radius.
#pragma once

#include <glm/vec3.hpp>

namespace raykit {

/// The sphere \f$ |\mathbf{x} - \mathbf{c}|^2 = r^2 \f$.
///
/// A radius that is zero, negative, NaN or infinite describes no sphere: the
/// reference solutions report no intersection for it.
struct Sphere {
    glm::vec3 center;  ///< \f$\mathbf{c}\f$, in scene units.
    float radius;      ///< \f$r > 0\f$, in scene units.
};

}  // namespace raykit
