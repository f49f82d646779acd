/// @brief Writing 8-bit RGBA images as PNG files (libpng).
#pragma once

#include <cstdint>
#include <span>
#include <string>

namespace engine {

/// How a PNG is compressed: zlib's level (1 fastest .. 9 smallest) and the row filter PNG
/// applies before it. libpng's default (adaptive: it tries all five filters on every row) is
/// the slowest, and on rendered walls, whose CT noise defeats the filters' prediction, it does
/// not even give smaller files than no filter (docs/benchmarks/stereo.md, "PNG encoding").
enum class PngFilter { None, Sub, Up, Paeth, Adaptive };
struct PngEncoding {
    int zlibLevel = 6;
    PngFilter filter = PngFilter::Adaptive;
};

/// The settings display renders use, chosen by cvc_bench png on rendered walls: no filter at
/// level 3 encodes a 1400x1050 wall in 57 ms against 144 ms for the adaptive filter at the same
/// level, for a file 5 % larger.
inline constexpr PngEncoding kFastPngEncoding{3, PngFilter::None};

/// Writes `rgba` (width * height * 4 bytes, row 0 at the top) to `path` as an 8-bit RGBA PNG.
/// Refuses to replace an existing file unless `overwrite`; throws std::runtime_error naming
/// the path when the file cannot be written (missing or read-only folder, full disk).
void writePng(const std::string& path, int width, int height, std::span<const uint8_t> rgba, bool overwrite,
              const PngEncoding& encoding = {});

}  // namespace engine
