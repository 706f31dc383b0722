/// \file canvas.hpp
/// \brief A canvas: the picture being rendered, one Color per pixel.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

#include "raykit/color.hpp"

namespace raykit {

/// A width x height grid of colours, black when created.
///
/// Pixel `(i, j)` is column `i` (0 at the left) of row `j`
/// (0 at the **top**), the order in which image files store them.
class Canvas {
public:
    /// Largest number of pixels a canvas may hold (about 67 million).
    static constexpr long long max_pixels = 1LL << 26;

    /// A black canvas of \p width x \p height pixels. Throws std::invalid_argument when a side is below 1
    /// or the canvas would hold more than max_pixels.
    /// \param width  columns, >= 1.
    /// \param height rows, >= 1.
    Canvas(int width, int height) : width_(width), height_(height) {
        if (width < 1 || height < 1 || static_cast<long long>(width) * height > max_pixels) {
            throw std::invalid_argument("Canvas: a size of " + std::to_string(width) + " x " +
                                        std::to_string(height) + " pixels is not possible");
        }
        pixels_.assign(static_cast<std::size_t>(width) * static_cast<std::size_t>(height), Color(0.0f));
    }

    /// \return the width in pixels.
    int width() const { return width_; }
    /// \return the height in pixels.
    int height() const { return height_; }

    /// The colour of pixel (i, j): column i, row j. Throws std::out_of_range
    /// outside the canvas, so a loop that goes one pixel too far is caught
    /// here instead of silently writing over memory.
    /// \param i the column, 0 at the left.
    /// \param j the row, 0 at the top.
    /// \return the pixel's colour, to read or to write.
    Color& at(int i, int j) { return pixels_[index(i, j)]; }
    /// The colour of pixel (i, j), read only; same rules as the other at().
    /// \param i the column, 0 at the left.
    /// \param j the row, 0 at the top.
    /// \return the pixel's colour.
    const Color& at(int i, int j) const { return pixels_[index(i, j)]; }

private:
    std::size_t index(int i, int j) const {
        if (i < 0 || i >= width_ || j < 0 || j >= height_) {
            throw std::out_of_range("Canvas::at(" + std::to_string(i) + ", " + std::to_string(j) +
                                    "): outside the " + std::to_string(width_) + " x " +
                                    std::to_string(height_) + " canvas");
        }
        return static_cast<std::size_t>(j) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(i);
    }

    int width_;
    int height_;
    std::vector<Color> pixels_;  // row by row, top row first
};

}  // namespace raykit
