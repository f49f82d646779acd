/// @brief Writing 8-bit RGBA images as PNG files (libpng).
#pragma once

#include <cstdint>
#include <span>
#include <string>

namespace engine {

/// Writes `rgba` (width * height * 4 bytes, row 0 at the top) to `path` as an 8-bit RGBA PNG.
/// Refuses to replace an existing file unless `overwrite`; throws std::runtime_error naming
/// the path when the file cannot be written (missing or read-only folder, full disk).
/// `compressionLevel` is zlib's: 1 is fastest, 9 smallest.
void writePng(const std::string& path, int width, int height, std::span<const uint8_t> rgba, bool overwrite,
              int compressionLevel = 6);

}  // namespace engine
