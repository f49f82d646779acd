#include "engine/output/png_writer.h"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <stdexcept>

#include <png.h>

namespace engine {
namespace {

struct FileCloser {
    void operator()(std::FILE* file) const { std::fclose(file); }
};

[[noreturn]] void onPngError(png_structp png, png_const_charp message) {
    auto* error = static_cast<std::string*>(png_get_error_ptr(png));
    *error = message;
    png_longjmp(png, 1);
}

void onPngWarning(png_structp, png_const_charp) {}

int filterFlags(PngFilter filter) {
    switch (filter) {
        case PngFilter::None: return PNG_FILTER_NONE;
        case PngFilter::Sub: return PNG_FILTER_SUB;
        case PngFilter::Up: return PNG_FILTER_UP;
        case PngFilter::Paeth: return PNG_FILTER_PAETH;
        case PngFilter::Adaptive: return PNG_ALL_FILTERS;
    }
    return PNG_ALL_FILTERS;
}

/// A PNG cut short (a full disk, a file-size limit) is removed: no half-written image is left
/// where a finished one is expected.
void removePartialFile(const std::string& path) {
    std::error_code ignored;
    std::filesystem::remove(path, ignored);
}

}  // namespace

void writePng(const std::string& path, int width, int height, std::span<const uint8_t> rgba, bool overwrite,
              const PngEncoding& encoding) {
    if (width < 1 || height < 1 || rgba.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 4) {
        throw std::invalid_argument(path + ": PNG pixel buffer does not match " + std::to_string(width) + "x" +
                                    std::to_string(height) + " RGBA");
    }
    if (!overwrite && std::filesystem::exists(path)) {
        throw std::runtime_error(path + ": exists already (pass --force to replace it)");
    }
    std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "wb"));
    if (!file) throw std::runtime_error(path + ": cannot open for writing (" + std::strerror(errno) + ")");

    std::string error;
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &error, onPngError, onPngWarning);
    png_infop info = png ? png_create_info_struct(png) : nullptr;
    if (png == nullptr || info == nullptr) {
        png_destroy_write_struct(&png, &info);
        throw std::runtime_error(path + ": cannot start the PNG encoder");
    }
    // libpng reports errors by longjmp; nothing with a destructor may be created below this.
    errno = 0;  // libpng's "Write Error" does not say why; the failed fwrite's errno does
    if (setjmp(png_jmpbuf(png))) {
        const int writeErrno = errno;
        png_destroy_write_struct(&png, &info);
        file.reset();
        removePartialFile(path);
        throw std::runtime_error(path + ": PNG write failed (" + error +
                                 (writeErrno != 0 ? std::string(": ") + std::strerror(writeErrno) : std::string()) + ")");
    }
    png_init_io(png, file.get());
    png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), 8, PNG_COLOR_TYPE_RGBA,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_compression_level(png, std::clamp(encoding.zlibLevel, 1, 9));
    png_set_filter(png, PNG_FILTER_TYPE_BASE, filterFlags(encoding.filter));
    png_write_info(png, info);
    for (int row = 0; row < height; ++row) {
        png_write_row(png, rgba.data() + static_cast<std::size_t>(row) * static_cast<std::size_t>(width) * 4);
    }
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    if (std::fflush(file.get()) != 0 || std::ferror(file.get()) || std::fclose(file.release()) != 0) {
        const int writeErrno = errno;
        file.reset();
        removePartialFile(path);
        throw std::runtime_error(path + ": write failed (" + std::strerror(writeErrno) + ")");
    }
}

}  // namespace engine
