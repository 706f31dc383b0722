// raykit_imgdiff REFERENCE.png IMAGE.png DIFF.png
//
// Compares two images pixel by pixel and writes DIFF.png: the reference in
// dim grey, with every pixel where IMAGE differs marked in magenta. Prints
// "DIFFERING NEAR_EDGE TOTAL" on stdout, NEAR_EDGE counting the differing
// pixels whose colour in IMAGE is that of a neighbour in the reference: an
// edge one pixel off, which rounding can cause at some sizes (and so can a
// half-pixel shift of the camera). Exit status: 0 compared (whatever the count),
// 2 bad arguments, unreadable images or different sizes, 5 DIFF not written.
#include <cstdio>
#include <exception>
#include <iostream>

#include "image.hpp"

using namespace raykit::tool;

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
    Image diff{reference.width, reference.height, std::vector<unsigned char>(reference.rgb.size())};
    long long differing = 0, near_edge = 0;
    const auto same = [](const unsigned char* a, const unsigned char* b) {
        return a[0] == b[0] && a[1] == b[1] && a[2] == b[2];
    };
    for (int j = 0; j < reference.height; ++j) {
        for (int i = 0; i < reference.width; ++i) {
            const unsigned char* r = reference.pixel(i, j);
            const unsigned char* p = image.pixel(i, j);
            unsigned char* d = diff.pixel(i, j);
            if (!same(r, p)) {
                ++differing;
                bool edge = false;
                for (int dj = -1; dj <= 1; ++dj) {
                    for (int di = -1; di <= 1; ++di) {
                        const int ni = i + di, nj = j + dj;
                        if (ni < 0 || nj < 0 || ni >= reference.width || nj >= reference.height) continue;
                        edge = edge || same(reference.pixel(ni, nj), p);
                    }
                }
                near_edge += edge;
                d[0] = 255, d[1] = 0, d[2] = 255;
            } else {
                // The reference's brightness, dimmed, as a backdrop for the marks.
                const int grey = (r[0] * 30 + r[1] * 59 + r[2] * 11) / 100;
                d[0] = d[1] = d[2] = static_cast<unsigned char>(40 + grey / 3);
            }
        }
    }
    try {
        write_png(diff, argv[3]);
    } catch (const std::exception& e) {
        std::cerr << e.what() << "\n";
        return 5;
    }
    std::cout << differing << " " << near_edge << " " << static_cast<long long>(reference.width) * reference.height << "\n";
    return 0;
}
