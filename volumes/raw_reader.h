/// @brief Headerless raw volumes: the caller states dims, scalar type, byte order and spacing.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "volumes/voxel_decode.h"
#include "volumes/volume.h"

namespace volumes {

/// What a raw file cannot say about itself. The grid is axis-aligned LPS with origin 0.
struct RawOptions {
    std::array<int, 3> dims{0, 0, 0};
    glm::dvec3 spacingMm{1.0, 1.0, 1.0};
    StoredFormat format;            ///< type, byte order, HU = stored * slope + intercept
    std::uint64_t headerBytes = 0;  ///< bytes to skip before the first voxel
};

/// Parses a compact description such as "512x512x451:int16:0.7x0.7x1.25", optionally followed
/// by ":big" (big-endian), ":skip=N" (header bytes) and ":slope=S" / ":intercept=I".
/// Types: int8 uint8 int16 uint16 int32 uint32 float double. Throws VolumeError naming the
/// part that is wrong (this text comes from the command line).
RawOptions parseRawSpec(const std::string& spec);

/// Reads `path` as x-fastest voxels described by `options`. The file must hold exactly
/// headerBytes + voxel count * value size bytes; anything else is an error, since a raw file
/// whose size disagrees with its description was described wrongly.
Volume readRaw(const std::string& path, const RawOptions& options);

}  // namespace volumes
