// Step 05: the empty Cornell box, the model.           <-- this file is yours
//
// Task:    steps/05_cornell_box/README.md
// Lecture: lectures/05-cornell-box.md (sections 2 and 3 give the numbers)
// Check:   ./kit check 5
//
// The declarations, with their full contract, are in
// include/raykit/cornell_box.hpp (read it, do not edit it).
// Replace each `not_implemented_yet(...)` line with your code.

#include "raykit/cornell_box.hpp"

#include "raykit/not_implemented.hpp"

namespace raykit {

Scene cornell_box() {
    not_implemented_yet("cornell_box");
}

Camera cornell_camera(int width, int height) {
    not_implemented_yet("cornell_camera", width, height);
}

}  // namespace raykit
