/// @brief Reading the per-pixel first-hit positions that `cvc render --hits` writes
/// (engine/output/hit_image_writer.h), so distances can be measured on a rendered wall
/// without Vulkan: a pinhole render's NRRD of float32 4-vectors (x, y, z in volume millimetres,
/// w = 1 hit / 0 miss; raw little-endian) and a display render's frame_NNNN/EYE/WALL_hits.nrrd
/// (gzip-compressed float32 3-vectors, NaN where the ray missed). Row 0 is the image's top.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace colon {

/// Largest image side accepted (pixels), as the renderer's kMaxImageSide.
inline constexpr int kMaxHitImageSide = 16384;

struct HitImage {
    int width = 0;
    int height = 0;
    std::vector<glm::dvec3> hitMm;  ///< width * height, row-major from the top row; (0, 0, 0) where missed
    std::vector<uint8_t> isHit;     ///< 1 where the ray hit the surface

    std::size_t index(int x, int y) const {
        return static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x);
    }
    bool contains(int x, int y) const { return x >= 0 && y >= 0 && x < width && y < height; }
    bool hitAt(int x, int y) const { return contains(x, y) && isHit[index(x, y)] != 0; }
};

/// Reads a hit image: NRRD with "type: float", "dimension: 3", sizes "3 W H" or "4 W H",
/// encoding raw or gzip, little-endian, data attached. Throws ColonError naming the file and what is
/// wrong for anything else: not NRRD, another type or shape, a detached data file, sides outside
/// 1..kMaxHitImageSide, data shorter or longer than the sizes say, a non-finite position where the
/// pixel is a hit (w > 0 in the 4-vector form; in the 3-vector form a miss is all three NaN).
HitImage readHitImage(const std::string& path);

}  // namespace colon
