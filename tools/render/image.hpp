// Images for the render tool: 8-bit RGB pixels, PNG files in and out.
#pragma once

#include <string>
#include <vector>

#include "raykit/canvas.hpp"

namespace raykit::tool {

/// An 8-bit RGB image, row by row from the top, 3 bytes a pixel.
struct Image {
    int width = 0;
    int height = 0;
    std::vector<unsigned char> rgb;

    unsigned char* pixel(int i, int j) { return &rgb[3 * (static_cast<std::size_t>(j) * width + i)]; }
    const unsigned char* pixel(int i, int j) const { return &rgb[3 * (static_cast<std::size_t>(j) * width + i)]; }
};

/// Each channel clamped to [0, 1] and scaled to 0..255, rounded; NaN becomes 0.
Image to_image(const Canvas& canvas);

/// Writes `image` as a PNG file at `path`. The bytes go to `path.tmp` first,
/// which is then renamed, so `path` is either the old file or the whole new
/// one, never half written. Throws std::runtime_error with a clear message.
void write_png(const Image& image, const std::string& path);

/// Writes `text` to `path` the same way (temporary file, then rename).
void write_text(const std::string& text, const std::string& path);

/// Reads an 8-bit RGB PNG. Throws std::runtime_error with a clear message.
Image read_png(const std::string& path);

}  // namespace raykit::tool
