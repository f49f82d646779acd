/// @brief Writing the per-pixel first-hit positions (volume millimetres) as a float image.
#pragma once

#include <span>
#include <string>

namespace engine {

/// Writes `hitMm` (width * height * 4 floats: x, y, z in volume millimetres and 1 for a hit,
/// 0 for a miss; row 0 at the top) as a NRRD file of 4-vectors (attached raw little-endian
/// float), which numpy, 3D Slicer and teem read. Refuses to replace a file unless `overwrite`.
void writeHitImageNrrd(const std::string& path, int width, int height, std::span<const float> hitMm, bool overwrite);

/// Writes the hit positions of `hitMm` (the same 4 floats per pixel) as a gzip-compressed NRRD
/// of float32 3-vectors (x, y, z in volume millimetres; NaN where the ray missed), the format of
/// a display render's frame_NNNN/EYE/WALL_hits.nrrd. Refuses to replace a file unless `overwrite`.
void writeHitPositionsNrrd(const std::string& path, int width, int height, std::span<const float> hitMm,
                           bool overwrite);

}  // namespace engine
