/// \file color.hpp
/// \brief A colour: red, green and blue.
#pragma once

#include <glm/vec3.hpp>

namespace raykit {

/// Red, green and blue, each in `[0, 1]`: 0 is none, 1 is full.
///
/// In this course a colour is written to an image as it is, each channel
/// scaled to a byte (see Canvas and the render tool); no gamma, no tone mapping.
using Color = glm::vec3;

}  // namespace raykit
