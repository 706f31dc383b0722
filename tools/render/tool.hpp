// The render tool's shared part: its command line, a camera placed by eye and
// target, shading.
//
// Each step has its own program (raykit_render_stepNN), linked with that
// step's code, so a step that does not compile costs only its scenes. Every
// program also links step 05 and shoots the view rays with its view_ray():
// the tool computes nothing a step asks for (a student's handout carries
// these files), so a student's pictures are drawn with the student's own
// code, and a view_ray still to write is reported as such.
//
//   raykit_render_stepNN SCENE SHADING WIDTH HEIGHT OUT
//   raykit_render_stepNN --smoke OUT     (the first scene in its last shading, 40 x 30)
//
// OUT ending in .png gets the picture; OUT ending in .txt gets it as letters,
// one a pixel (see palette_letter). Exit status: 0 written, 2 bad arguments,
// 3 a function is still a stub (raykit::not_implemented), 4 the code under
// test threw, 5 the file could not be written.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "raykit/camera.hpp"
#include "raykit/canvas.hpp"

namespace raykit::tool {

/// One scene a program can render, in the shadings it knows.
struct SceneEntry {
    std::string name;
    std::vector<std::string> shadings;  // "flat" first
    std::function<Canvas(const std::string& shading, int width, int height)> render;
};

/// Parses the command line, renders, writes the file; returns the exit status.
int run(int argc, char** argv, const std::vector<SceneEntry>& scenes);

/// A camera at `eye` looking at `target`, `vertical_fov_degrees` high, for a
/// width x height image. `world_up` need not be perpendicular to the view.
Camera look_at(const glm::vec3& eye, const glm::vec3& target, const glm::vec3& world_up,
               float vertical_fov_degrees, int width, int height);

/// The usual picture of a unit normal: each component from [-1, 1] to [0, 1].
Color normal_color(const glm::vec3& unit_normal);

/// Letter for a flat colour of the Cornell box ('.', 'W', 'R', 'G', 'L'), '?' otherwise.
char palette_letter(const Color& color);

}  // namespace raykit::tool
