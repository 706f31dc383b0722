// Scenes of step 05: the empty Cornell box, drawn entirely by the step's own
// code: its model, its camera, its closest hit and its render loop.
#include "raykit/cornell_box.hpp"
#include "raykit/render.hpp"
#include "tool.hpp"

using namespace raykit;

namespace {

Canvas cornell(const std::string&, int width, int height) {
    return render(cornell_box(), cornell_camera(width, height));
}

}  // namespace

int main(int argc, char** argv) { return tool::run(argc, argv, {{"cornell_box", {"flat"}, cornell}}); }
