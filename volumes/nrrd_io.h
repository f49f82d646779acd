/// @brief NRRD (teem's "nearly raw raster data") reading and writing for CT volumes.
#pragma once

#include <string>

#include "volumes/volume.h"

namespace volumes {

/// Reads a 3D NRRD file with attached data, raw or gzip encoded, of any integer or float
/// scalar type whose values fit int16 HU. Spacing comes from `space directions` (or
/// `spacings`), origin from `space origin`; a RAS `space` is converted to LPS.
/// Throws VolumeError naming the file and the problem for anything else or anything wrong
/// (truncated data, sizes that disagree with the data, NaN voxels, absurd spacing).
Volume readNrrd(const std::string& path);

/// Writes `volume` as NRRD0004 with attached raw little-endian int16 data in LPS space.
/// Refuses (VolumeError) to replace an existing file unless `overwrite` is true.
void writeNrrd(const Volume& volume, const std::string& path, bool overwrite = false);

}  // namespace volumes
