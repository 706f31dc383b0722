// raykit_imgdiff REFERENCE.png IMAGE.png DIFF.png
//
// Compares two images pixel by pixel and prints, on stdout,
//
//     DIFFERING EDGE TOTAL LEVEL UPSIDE_DOWN MIRRORED
//
// where DIFFERING counts the pixels that differ at all, and each of them is of
// exactly one kind:
//   LEVEL  every channel within one level (of 255) of the reference: a smooth
//          shading (the normals) whose value sits near a rounding boundary of
//          the 8-bit conversion, which any correct float answer may cross;
//   EDGE   not LEVEL, but the colour of a neighbour in the reference, and the
//          reference's own colour there is still beside it in the image: an
//          edge one pixel off, which rounding can cause where a ray grazes an
//          object (and so can a camera shifted by half a pixel);
//   other  DIFFERING - LEVEL - EDGE: a colour the reference has nowhere near,
//          or a whole region of another colour: a light that is missing is
//          drawn in the ceiling's colour, which the reference has next to the
//          light's border, but the light's colour is nowhere beside it in the
//          image, so no edge moved there: the region is gone.
// UPSIDE_DOWN and MIRRORED count the pixels whose colour differs by more than
// one level from the reference turned upside down (row j compared with row
// h - 1 - j) and mirrored left to right: 0 or nearly for a picture whose rows
// count from the bottom or whose right points left, which as it stands is
// mostly moved edges and would read as "an edge moved by a pixel".
// The caller (./kit render) decides how many of the first two kinds a correct
// answer may have; here they are only counted.
//
// DIFF.png shows the reference in dim grey with each differing pixel in a
// colour of its kind (LEVEL cyan, EDGE yellow, other magenta) and a ring of
// the same colour around it: a single pixel in a 256 x 256 picture is
// invisible at the size an image viewer first shows it, its ring is not.
//
// Exit status: 0 compared (whatever the count), 2 bad arguments, unreadable
// images or different sizes, 5 DIFF not written.
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <iostream>
#include <vector>

#include "image.hpp"

using namespace raykit::tool;

namespace {

enum class Kind { same, level, edge, other };

bool same_colour(const unsigned char* a, const unsigned char* b) { return a[0] == b[0] && a[1] == b[1] && a[2] == b[2]; }

bool within_one_level(const unsigned char* a, const unsigned char* b) {
    for (int k = 0; k < 3; ++k)
        if (std::abs(int(a[k]) - int(b[k])) > 1) return false;
    return true;
}

// What kind of difference pixel (i, j) of `image` is from `reference`.
Kind classify(const Image& reference, const Image& image, int i, int j) {
    const unsigned char* r = reference.pixel(i, j);
    const unsigned char* p = image.pixel(i, j);
    if (same_colour(r, p)) return Kind::same;
    if (within_one_level(r, p)) return Kind::level;
    // An edge moved by a pixel: the image's colour is a neighbour's in the reference, and the
    // reference's colour here is a neighbour's in the image (the region it belongs to is still there,
    // a pixel over). Only the first holds where a region is missing or added whole.
    bool taken = false, kept = false;
    for (int dj = -1; dj <= 1; ++dj) {
        for (int di = -1; di <= 1; ++di) {
            const int ni = i + di, nj = j + dj;
            if (ni < 0 || nj < 0 || ni >= reference.width || nj >= reference.height) continue;
            taken = taken || same_colour(reference.pixel(ni, nj), p);
            kept = kept || same_colour(image.pixel(ni, nj), r);
        }
    }
    return taken && kept ? Kind::edge : Kind::other;
}

void paint(unsigned char* d, Kind kind) {
    switch (kind) {
        case Kind::level: d[0] = 0, d[1] = 230, d[2] = 230; break;
        case Kind::edge: d[0] = 255, d[1] = 220, d[2] = 0; break;
        default: d[0] = 255, d[1] = 0, d[2] = 255; break;
    }
}

// The ring's radii in pixels: wide enough to see at a glance, thin enough not
// to hide its neighbours' marks.
constexpr int ring_inner = 4, ring_outer = 6;
constexpr long long max_ringed = 4096;

// Draws a ring around (i, j) on the pixels that do not differ themselves (a
// differing pixel keeps its own mark).
void ring(Image& diff, const std::vector<Kind>& kinds, int i, int j, Kind kind) {
    for (int dj = -ring_outer; dj <= ring_outer; ++dj) {
        for (int di = -ring_outer; di <= ring_outer; ++di) {
            const int r2 = di * di + dj * dj;
            if (r2 < ring_inner * ring_inner || r2 > ring_outer * ring_outer) continue;
            const int ni = i + di, nj = j + dj;
            if (ni < 0 || nj < 0 || ni >= diff.width || nj >= diff.height) continue;
            if (kinds[static_cast<std::size_t>(nj) * diff.width + ni] != Kind::same) continue;
            paint(diff.pixel(ni, nj), kind);
        }
    }
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 4) {
        std::cerr << "usage: raykit_imgdiff REFERENCE.png IMAGE.png DIFF.png\n";
        return 2;
    }
    Image reference, image;
    try {
        reference = read_png(argv[1]);
        image = read_png(argv[2]);
    } catch (const std::exception& e) {
        std::cerr << e.what() << "\n";
        return 2;
    }
    if (reference.width != image.width || reference.height != image.height) {
        std::cerr << argv[2] << " is " << image.width << " x " << image.height << " pixels, the reference "
                  << argv[1] << " is " << reference.width << " x " << reference.height << "\n";
        return 2;
    }
    const int w = reference.width, h = reference.height;
    Image diff{w, h, std::vector<unsigned char>(reference.rgb.size())};
    std::vector<Kind> kinds(static_cast<std::size_t>(w) * h);
    long long differing = 0, edge = 0, level = 0;
    for (int j = 0; j < h; ++j) {
        for (int i = 0; i < w; ++i) {
            const Kind kind = classify(reference, image, i, j);
            kinds[static_cast<std::size_t>(j) * w + i] = kind;
            differing += kind != Kind::same;
            edge += kind == Kind::edge;
            level += kind == Kind::level;
            // The reference's brightness, dimmed, as a backdrop for the marks.
            const unsigned char* r = reference.pixel(i, j);
            const int grey = (r[0] * 30 + r[1] * 59 + r[2] * 11) / 100;
            unsigned char* d = diff.pixel(i, j);
            d[0] = d[1] = d[2] = static_cast<unsigned char>(40 + grey / 3);
        }
    }
    // Rings first, marks last: with many differences the marks stay on top.
    // Past a few thousand differences the marks alone are visible, and rings
    // would only cost time (169 pixels each).
    const auto kind_at = [&](int i, int j) { return kinds[static_cast<std::size_t>(j) * w + i]; };
    if (differing <= max_ringed) {
        for (int j = 0; j < h; ++j)
            for (int i = 0; i < w; ++i)
                if (kind_at(i, j) != Kind::same) ring(diff, kinds, i, j, kind_at(i, j));
    }
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i)
            if (kind_at(i, j) != Kind::same) paint(diff.pixel(i, j), kind_at(i, j));
    try {
        write_png(diff, argv[3]);
    } catch (const std::exception& e) {
        std::cerr << e.what() << "\n";
        return 5;
    }
    long long upside_down = 0, mirrored = 0;
    for (int j = 0; j < h; ++j) {
        for (int i = 0; i < w; ++i) {
            upside_down += !within_one_level(reference.pixel(i, h - 1 - j), image.pixel(i, j));
            mirrored += !within_one_level(reference.pixel(w - 1 - i, j), image.pixel(i, j));
        }
    }
    std::cout << differing << " " << edge << " " << static_cast<long long>(w) * h << " " << level << " "
              << upside_down << " " << mirrored << "\n";
    return 0;
}
