/// @brief OpenVDB (.vdb) reading and writing: a float grid in HU, background -1000 (air).
#pragma once

#include <string>

#include "volumes/brick_minmax.h"
#include "volumes/volume.h"

namespace volumes {

/// Name of the grid writeVdb stores and readVdb looks for first.
inline constexpr const char* kVdbGridName = "hu";
/// Background (the value of every voxel not stored in the tree): air.
inline constexpr float kVdbBackgroundHu = -1000.0f;

/// Reads the float grid named `gridName` (empty: "hu", else the file's first float grid).
/// The volume spans the index box recorded by writeVdb ("cvc_dims" metadata) or, for other
/// files, the grid's active-voxel bounding box; the grid's linear transform gives spacing,
/// direction and origin (world space is read as LPS millimetres). Values are rounded to int16
/// HU; NaN, Inf or out-of-range values and non-linear transforms throw VolumeError.
/// When `bricks` is non-null it receives the brick min/max, built from the tree's leaves and
/// tiles (exactly equal to buildBrickMinMax on the returned volume).
Volume readVdb(const std::string& path, BrickMinMax* bricks = nullptr, const std::string& gridName = {});

/// Writes `volume` as a float grid "hu" with background -1000: voxels equal to -1000 are
/// inactive and, in 8^3 bricks that hold nothing else, not stored at all. The transform maps
/// index space to LPS millimetres. Refuses to replace an existing file unless `overwrite`.
void writeVdb(const Volume& volume, const std::string& path, bool overwrite = false);

}  // namespace volumes
