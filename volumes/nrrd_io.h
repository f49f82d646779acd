/// @brief NRRD (teem's "nearly raw raster data") reading and writing for CT volumes.
#pragma once

#include <array>
#include <cstdint>
#include <istream>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "volumes/voxel_decode.h"
#include "volumes/volume.h"

namespace volumes {

/// The fields of a NRRD header that a CT volume needs.
struct NrrdHeader {
    ScalarType type = ScalarType::Int16;
    std::array<int, 3> sizes{0, 0, 0};
    std::string encoding = "raw";  ///< "raw" or "gzip"
    bool isBigEndian = false;
    bool isRas = false;  ///< `space` is right-anterior-superior
    bool hasSpaceDirections = false;
    glm::dmat3 spaceDirections{1.0};  ///< columns: the grid axes in the header's space, mm
    glm::dvec3 spacings{1.0};         ///< `spacings`, used when there are no space directions
    glm::dvec3 origin{0.0};
    std::string dataFile;          ///< detached data: path as written in the header; empty if attached
    std::int64_t byteSkip = 0;     ///< `byte skip` (-1: the data are the file's last bytes)
    std::int64_t lineSkip = 0;     ///< `line skip`: text lines before the data
    std::uint64_t dataOffset = 0;  ///< attached data: offset of the first data byte
};

/// Parses a NRRD header from `in` (at the start of the file) up to the blank line that ends
/// it. Throws VolumeError naming `source`, the field, its value and what was expected.
NrrdHeader parseNrrdHeader(const std::string& source, std::istream& in);

/// Reads a 3D NRRD volume: attached (.nrrd) or detached (.nhdr + `data file`) data, raw or
/// gzip encoded, of any integer or float scalar type whose values fit int16 HU, decoded in
/// chunks straight into the volume (no second full-size copy). Spacing comes from
/// `space directions` (or `spacings`), origin from `space origin`; a RAS `space` is
/// converted to LPS. Throws VolumeError naming the file and the problem for anything else or
/// anything wrong (truncated data, sizes that disagree with the data, NaN voxels, absurd
/// spacing).
Volume readNrrd(const std::string& path);

/// Writes `volume` as NRRD0004 with attached raw little-endian int16 data in LPS space.
/// Refuses (VolumeError) to replace an existing file unless `overwrite` is true.
void writeNrrd(const Volume& volume, const std::string& path, bool overwrite = false);

/// A NRRD header's `key:=value` pairs, in the order they are written.
using NrrdKeyValues = std::vector<std::pair<std::string, std::string>>;

/// Writes `labels` (one uint8 per voxel of `grid`, x fastest) as NRRD0004 on `grid`'s LPS
/// geometry, gzip encoded, with `keyValues` in the header: the form of a 3D Slicer segmentation
/// (.seg.nrrd). Refuses (VolumeError) a label count that does not match the grid, a pair that
/// cannot be written on one header line, and replacing a file unless `overwrite` is true.
void writeLabelNrrd(const Volume& grid, std::span<const std::uint8_t> labels, const NrrdKeyValues& keyValues,
                    const std::string& path, bool overwrite = false);

}  // namespace volumes
