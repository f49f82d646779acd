#include "engine/output/png_reader.h"

#include <stdexcept>

#include <png.h>

namespace engine {

colon::RgbaImage readPng(const std::string& path) {
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&image, path.c_str())) {
        throw std::runtime_error(path + ": cannot read the PNG (" + image.message + ")");
    }
    image.format = PNG_FORMAT_RGBA;
    colon::RgbaImage pixels;
    pixels.width = static_cast<int>(image.width);
    pixels.height = static_cast<int>(image.height);
    pixels.rgba.resize(PNG_IMAGE_SIZE(image));
    if (!png_image_finish_read(&image, nullptr, pixels.rgba.data(), 0, nullptr)) {
        png_image_free(&image);
        throw std::runtime_error(path + ": cannot decode the PNG (" + image.message + ")");
    }
    return pixels;
}

}  // namespace engine
