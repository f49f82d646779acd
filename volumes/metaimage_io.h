/// @brief MetaImage (ITK's .mha with attached data, .mhd with a separate data file) reading.
#pragma once

#include <cstdint>
#include <istream>
#include <string>

#include "volumes/voxel_decode.h"
#include "volumes/volume.h"

namespace volumes {

/// The fields of a MetaImage header that a CT volume needs. Positions are in LPS millimetres
/// (ITK writes physical space as LPS); `directionLps` columns are the grid axes.
struct MetaImageHeader {
    std::array<int, 3> dims{0, 0, 0};
    glm::dvec3 spacingMm{1.0, 1.0, 1.0};
    glm::dvec3 originLps{0.0, 0.0, 0.0};
    glm::dmat3 directionLps{1.0};
    StoredFormat format;
    bool isCompressed = false;
    std::string dataFile;          ///< "LOCAL" or a path relative to the header's folder
    std::int64_t headerBytes = 0;  ///< HeaderSize: bytes to skip in a separate data file (-1: to fit)
    std::uint64_t dataOffset = 0;  ///< for LOCAL: offset of the first data byte in the file
};

/// Parses the text header from `in` (positioned at the start of the file) up to and including
/// the ElementDataFile line, which MetaImage requires to be last. Throws VolumeError naming
/// `source`, the field, its value and what was expected.
MetaImageHeader parseMetaImageHeader(const std::string& source, std::istream& in);

/// Reads a .mha or .mhd volume (raw or zlib-compressed data, any scalar type that fits int16
/// HU). Throws VolumeError for anything unsupported, truncated or inconsistent.
Volume readMetaImage(const std::string& path);

}  // namespace volumes
