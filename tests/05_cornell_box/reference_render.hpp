// The empty Cornell box at 48 x 32 pixels, rendered by the reference solution:
// one letter a pixel, W white, R red, G green, L light, . black (nothing hit).
// Written by ./kit render --refresh; ./kit test checks that it is up to date.
#pragma once

namespace cornell_reference {

constexpr int width = 48;
constexpr int height = 32;
constexpr const char* rows[height] = {
    "................................................",
    "........RWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWG........",
    "........RRWWWWWWWWWWWWWWWWWWWWWWWWWWWWGG........",
    "........RRRWWWWWWWWWWWWWWWWWWWWWWWWWWGGG........",
    "........RRRRWWWWWWWWWLLLLLLWWWWWWWWWGGGG........",
    "........RRRRRWWWWWWWWWWWWWWWWWWWWWWGGGGG........",
    "........RRRRRRWWWWWWWWWWWWWWWWWWWWGGGGGG........",
    "........RRRRRRRWWWWWWWWWWWWWWWWWWGGGGGGG........",
    "........RRRRRRRWWWWWWWWWWWWWWWWWWGGGGGGG........",
    "........RRRRRRRWWWWWWWWWWWWWWWWWWGGGGGGG........",
    "........RRRRRRRWWWWWWWWWWWWWWWWWWGGGGGGG........",
    "........RRRRRRRWWWWWWWWWWWWWWWWWWGGGGGGG........",
    "........RRRRRRRWWWWWWWWWWWWWWWWWWGGGGGGG........",
    "........RRRRRRRWWWWWWWWWWWWWWWWWWGGGGGGG........",
    "........RRRRRRRWWWWWWWWWWWWWWWWWWGGGGGGG........",
    "........RRRRRRRWWWWWWWWWWWWWWWWWWGGGGGGG........",
    "........RRRRRRRWWWWWWWWWWWWWWWWWWGGGGGGG........",
    "........RRRRRRRWWWWWWWWWWWWWWWWWWGGGGGGG........",
    "........RRRRRRRWWWWWWWWWWWWWWWWWWGGGGGGG........",
    "........RRRRRRRWWWWWWWWWWWWWWWWWWGGGGGGG........",
    "........RRRRRRRWWWWWWWWWWWWWWWWWWGGGGGGG........",
    "........RRRRRRRWWWWWWWWWWWWWWWWWWGGGGGGG........",
    "........RRRRRRRWWWWWWWWWWWWWWWWWWGGGGGGG........",
    "........RRRRRRRWWWWWWWWWWWWWWWWWWGGGGGGG........",
    "........RRRRRRRWWWWWWWWWWWWWWWWWWGGGGGGG........",
    "........RRRRRRWWWWWWWWWWWWWWWWWWWWGGGGGG........",
    "........RRRRRWWWWWWWWWWWWWWWWWWWWWWGGGGG........",
    "........RRRRWWWWWWWWWWWWWWWWWWWWWWWWGGGG........",
    "........RRRWWWWWWWWWWWWWWWWWWWWWWWWWWGGG........",
    "........RRWWWWWWWWWWWWWWWWWWWWWWWWWWWWGG........",
    "........RWWWWWWWWWWWWWWWWWWWWWWWWWWWWWWG........",
    "................................................",
};

}  // namespace cornell_reference
