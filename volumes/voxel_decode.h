/// @brief Turning stored voxel values (any scalar type, either byte order, raw or zlib/gzip
/// compressed) into int16 Hounsfield units, in bounded chunks so that no loader needs a second
/// full-size copy of the volume in memory.
#pragma once

#include <cstddef>
#include <cstdint>
#include <istream>
#include <span>
#include <string>

#include "volumes/volume.h"

namespace volumes {

/// Scalar types the loaders accept on disk.
enum class ScalarType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

/// Bytes one stored value of `type` occupies.
std::size_t bytesPerValue(ScalarType type);

/// Lower-case name of `type` as the NRRD and raw options spell it ("int16", "float", ...).
std::string scalarTypeName(ScalarType type);

/// How voxels are stored and how they map to HU: hu = stored * slope + intercept.
struct StoredFormat {
    ScalarType type = ScalarType::Int16;
    bool isBigEndian = false;
    double slope = 1.0;
    double intercept = 0.0;
};

/// Converts `hu.size()` stored values starting at `bytes` to HU, rounding to nearest.
/// Throws VolumeError naming `source` and the voxel index (offset by `firstIndex`) when a value
/// (after scaling) is NaN or infinite or does not fit int16.
void huFromStored(const std::string& source, const StoredFormat& format, const unsigned char* bytes,
                  std::span<int16_t> hu, std::size_t firstIndex = 0);

/// Reads exactly hu.size() stored values from `in` (positioned at the first voxel) and
/// converts them to HU. Throws VolumeError when the stream ends early ("truncated").
void readRawHu(const std::string& source, std::istream& in, const StoredFormat& format, std::span<int16_t> hu);

/// Inflates a zlib or gzip stream (detected from its first bytes) from `in` and converts the
/// hu.size() values it must hold. Throws VolumeError when the stream is corrupt, ends early,
/// or holds more data than the header calls for.
void readCompressedHu(const std::string& source, std::istream& in, const StoredFormat& format, std::span<int16_t> hu);

}  // namespace volumes
