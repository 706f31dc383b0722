// raykit_imgdiff REFERENCE.png IMAGE.png DIFF.png
//
// Compares two images pixel by pixel and writes DIFF.png: the reference in
// dim grey, with every pixel where IMAGE differs marked in magenta. Prints
// "DIFFERING TOTAL" on stdout. Exit status: 0 compared (whatever the count),
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
    long long differing = 0;
    for (int j = 0; j < reference.height; ++j) {
        for (int i = 0; i < reference.width; ++i) {
            const unsigned char* r = reference.pixel(i, j);
            const unsigned char* p = image.pixel(i, j);
            unsigned char* d = diff.pixel(i, j);
            if (r[0] != p[0] || r[1] != p[1] || r[2] != p[2]) {
                ++differing;
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
    std::cout << differing << " " << static_cast<long long>(reference.width) * reference.height << "\n";
    return 0;
}
