// The Cornell box table. See box.hpp.

#include "box.hpp"

namespace raykit::bench {

// axis, offset, lo (u, v), hi (u, v); u < v are the two other axes.
const Rect3 kCornellBox[kBoxRects] = {
    {0, 555, {0, 0}, {555, 555}},        // left wall (green), x = 555, y and z
    {0, 0, {0, 0}, {555, 555}},          // right wall (red), x = 0
    {1, 554, {213, 227}, {343, 332}},    // the light, y = 554, x and z
    {1, 0, {0, 0}, {555, 555}},          // floor, y = 0
    {1, 555, {0, 0}, {555, 555}},        // ceiling, y = 555
    {2, 555, {0, 0}, {555, 555}},        // back wall, z = 555, x and y
};

}  // namespace raykit::bench
