#include "image.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include <stb_image.h>
#include <stb_image_write.h>

namespace raykit::tool {

namespace {

unsigned char to_byte(float c) {
    if (!(c > 0.0f)) return 0;  // also NaN
    if (c >= 1.0f) return 255;
    return static_cast<unsigned char>(std::lround(c * 255.0f));
}

// Renames `tmp` over `path`, or removes `tmp` and throws.
void commit(const std::string& tmp, const std::string& path) {
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        const std::string reason = std::strerror(errno);
        std::remove(tmp.c_str());
        throw std::runtime_error("cannot write " + path + ": " + reason);
    }
}

}  // namespace

Image to_image(const Canvas& canvas) {
    Image image{canvas.width(), canvas.height(), {}};
    image.rgb.resize(3 * static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height));
    for (int j = 0; j < image.height; ++j) {
        for (int i = 0; i < image.width; ++i) {
            const Color& c = canvas.at(i, j);
            unsigned char* p = image.pixel(i, j);
            p[0] = to_byte(c.r);
            p[1] = to_byte(c.g);
            p[2] = to_byte(c.b);
        }
    }
    return image;
}

void write_png(const Image& image, const std::string& path) {
    const std::string tmp = path + ".tmp";
    const int ok = stbi_write_png(tmp.c_str(), image.width, image.height, 3, image.rgb.data(), 3 * image.width);
    if (!ok) {
        const std::string reason = std::strerror(errno);
        std::remove(tmp.c_str());
        throw std::runtime_error("cannot write " + path + ": " + reason);
    }
    commit(tmp, path);
}

void write_text(const std::string& text, const std::string& path) {
    const std::string tmp = path + ".tmp";
    {
        std::ofstream out(tmp, std::ios::binary);
        out << text;
        out.flush();
        if (!out) {
            const std::string reason = std::strerror(errno);
            out.close();
            std::remove(tmp.c_str());
            throw std::runtime_error("cannot write " + path + ": " + reason);
        }
    }
    commit(tmp, path);
}

Image read_png(const std::string& path) {
    int width = 0, height = 0, channels = 0;
    unsigned char* data = stbi_load(path.c_str(), &width, &height, &channels, 3);
    if (data == nullptr) {
        throw std::runtime_error("cannot read the image " + path + ": " + stbi_failure_reason());
    }
    Image image{width, height, {}};
    image.rgb.assign(data, data + 3 * static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
    stbi_image_free(data);
    return image;
}

}  // namespace raykit::tool
