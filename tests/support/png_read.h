/// @brief Reading an 8-bit RGBA PNG back (libpng's simplified API), so tests compare the pixels
/// of written files with images held in memory.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include <png.h>

namespace testing_support {

struct PngPixels {
    int width = 0;
    int height = 0;
    std::vector<uint8_t> rgba;
};

inline PngPixels readPng(const std::string& path) {
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&image, path.c_str())) throw std::runtime_error(path + ": " + image.message);
    image.format = PNG_FORMAT_RGBA;
    PngPixels pixels;
    pixels.width = static_cast<int>(image.width);
    pixels.height = static_cast<int>(image.height);
    pixels.rgba.resize(PNG_IMAGE_SIZE(image));
    if (!png_image_finish_read(&image, nullptr, pixels.rgba.data(), 0, nullptr)) {
        throw std::runtime_error(path + ": " + image.message);
    }
    return pixels;
}

}  // namespace testing_support
