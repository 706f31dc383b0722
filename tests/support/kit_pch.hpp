// The headers that every file of the kit's own programs reads (the judges, the dispatchers, the
// grader's support), compiled once as a precompiled header (CMakeLists.txt, raykit_kit_pch) and
// reused by each of them: parsing them was most of a judge's compile time at -O0.
// Only the standard library and GLM (not doctest, whose header defines a test suite that a
// dispatcher, which does not link doctest, cannot resolve): never a file a student writes, and never one of the
// kit's own headers, which each file still includes itself (so it compiles without this one too).
#pragma once

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
