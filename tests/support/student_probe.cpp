// The bundle's stand-in for a student's step file (CMakeLists.txt, RAYKIT_BUNDLE): compiled with the
// flags a student's file gets in their own check and in a grade, so that a check can compile the
// student's files with the very same command (tools/raykit/bundle.py). It includes what a step file
// includes first, the step header, and defines nothing.
#include "raykit/ray.hpp"
