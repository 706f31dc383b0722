#include "tool.hpp"

#include "raykit/scenes/cornell_box_data.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <iostream>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "image.hpp"
#include "raykit/not_implemented.hpp"

namespace raykit::tool {

namespace {

constexpr int max_side = 4096;

bool parse_size(const char* text, int& value) {
    char* end = nullptr;
    errno = 0;
    const long v = std::strtol(text, &end, 10);
    if (end == text || *end != '\0' || errno != 0 || v < 1 || v > max_side) return false;
    value = static_cast<int>(v);
    return true;
}

bool ends_with(const std::string& s, const std::string& suffix) {
    return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

int usage(const std::string& program, const std::vector<SceneEntry>& scenes, const std::string& problem) {
    std::cerr << program << ": " << problem << "\nusage: " << program
              << " SCENE SHADING WIDTH HEIGHT OUT.png|OUT.txt   (1 <= WIDTH, HEIGHT <= " << max_side
              << ")\n       " << program << " --smoke OUT.png   (the first scene, small)\nscenes:";
    for (const SceneEntry& s : scenes) {
        std::cerr << " " << s.name << " (";
        for (std::size_t k = 0; k < s.shadings.size(); ++k) std::cerr << (k ? ", " : "") << s.shadings[k];
        std::cerr << ")";
    }
    std::cerr << "\n";
    return 2;
}

std::string as_letters(const Canvas& canvas) {
    std::string text;
    for (int j = 0; j < canvas.height(); ++j) {
        for (int i = 0; i < canvas.width(); ++i) text += palette_letter(canvas.at(i, j));
        text += '\n';
    }
    return text;
}

}  // namespace

int run(int argc, char** argv, const std::vector<SceneEntry>& scenes) {
    const std::string program = argc > 0 ? argv[0] : "raykit_render";
    // "--smoke OUT": the build's smoke test, which names no scene (the build knows a step by its
    // file name only): the first scene in its last shading, the one that runs the most code.
    if (argc == 3 && std::string(argv[1]) == "--smoke" && !scenes.empty() && !scenes.front().shadings.empty()) {
        std::vector<std::string> args = {program, scenes.front().name, scenes.front().shadings.back(), "40", "30",
                                         argv[2]};
        std::vector<char*> pointers;
        for (std::string& a : args) pointers.push_back(a.data());
        return run(static_cast<int>(pointers.size()), pointers.data(), scenes);
    }
    if (argc != 6) return usage(program, scenes, "expected 5 arguments, got " + std::to_string(argc - 1));
    const std::string name = argv[1], shading = argv[2], out = argv[5];
    const SceneEntry* scene = nullptr;
    for (const SceneEntry& s : scenes) {
        if (s.name == name) scene = &s;
    }
    if (scene == nullptr) return usage(program, scenes, "no scene named '" + name + "'");
    bool known = false;
    for (const std::string& s : scene->shadings) known = known || s == shading;
    if (!known) return usage(program, scenes, "scene " + name + " has no shading '" + shading + "'");
    int width = 0, height = 0;
    if (!parse_size(argv[3], width) || !parse_size(argv[4], height)) {
        return usage(program, scenes, std::string("bad size ") + argv[3] + " x " + argv[4]);
    }
    if (!ends_with(out, ".png") && !ends_with(out, ".txt")) {
        return usage(program, scenes, "the output file must end in .png or .txt: " + out);
    }

    // Render first, entirely in memory: if the code under test throws or
    // crashes, no file has been touched.
    std::optional<Canvas> canvas;
    try {
        canvas.emplace(scene->render(shading, width, height));
    } catch (const raykit::not_implemented& e) {
        std::cerr << e.what() << "\n";
        return 3;
    } catch (const std::exception& e) {
        std::cerr << "the code threw an exception while rendering " << name << ": " << e.what() << "\n";
        return 4;
    } catch (...) {
        std::cerr << "the code threw something that is not a std::exception while rendering " << name << "\n";
        return 4;
    }
    if (canvas->width() != width || canvas->height() != height) {
        std::cerr << "render returned a " << canvas->width() << " x " << canvas->height() << " canvas for a "
                  << width << " x " << height << " camera\n";
        return 4;
    }
    try {
        if (ends_with(out, ".png")) {
            write_png(to_image(*canvas), out);
        } else {
            write_text(as_letters(*canvas), out);
        }
    } catch (const std::exception& e) {
        std::cerr << e.what() << "\n";
        return 5;
    }
    return 0;
}

Camera look_at(const glm::vec3& eye, const glm::vec3& target, const glm::vec3& world_up,
               float vertical_fov_degrees, int width, int height) {
    const glm::vec3 forward = glm::normalize(target - eye);
    // Gram-Schmidt: the part of world_up perpendicular to forward.
    const glm::vec3 up = glm::normalize(world_up - glm::dot(world_up, forward) * forward);
    const float film_height = 2.0f * std::tan(glm::radians(vertical_fov_degrees) / 2.0f);
    return Camera{eye, forward, up, 1.0f, film_height, width, height};
}

Color normal_color(const glm::vec3& n) { return 0.5f * (n + glm::vec3(1.0f)); }

char palette_letter(const Color& c) {
    struct Entry {
        char letter;
        Color color;
    };
    static const Entry palette[] = {{'.', {0, 0, 0}},
                                    {'W', scenes::cornell::white},
                                    {'R', scenes::cornell::red},
                                    {'G', scenes::cornell::green},
                                    {'L', scenes::cornell::light}};
    for (const Entry& e : palette) {
        if (glm::length(e.color - c) <= 0.005f) return e.letter;
    }
    return '?';
}

}  // namespace raykit::tool
