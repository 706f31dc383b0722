/// \file ray.hpp
/// \brief A ray: a start point and a direction.
#pragma once

#include <glm/vec3.hpp>

namespace raykit {

/// A ray is the set of points \f$ \mathbf{p}(t) = \mathbf{o} + t\,\mathbf{d} \f$.
///
/// - `origin` is \f$\mathbf{o}\f$, in scene units.
/// - `direction` is \f$\mathbf{d}\f$. It need **not** be unit length: a
///   distance along the ray is \f$ t\,|\mathbf{d}| \f$, so \f$t\f$ counts
///   multiples of \f$\mathbf{d}\f$, not scene units. A zero direction is a
///   degenerate ray that hits nothing.
///
/// Negative \f$t\f$ are points behind the origin; the intersection functions
/// report them in their root lists but a window `tmin >= 0` excludes them.
struct Ray {
    glm::vec3 origin;     ///< \f$\mathbf{o}\f$, where the ray starts.
    glm::vec3 direction;  ///< \f$\mathbf{d}\f$, any length but zero.
};

/// The point \f$ \mathbf{o} + t\,\mathbf{d} \f$ on \p ray.
///
/// \param ray the ray; its direction need not be unit length.
/// \param t   how many multiples of the direction to go from the origin;
///             negative values go backwards, behind the origin.
/// \return the point, in scene units.
inline glm::vec3 point_at(const Ray& ray, float t) {
    return ray.origin + t * ray.direction;
}

}  // namespace raykit
