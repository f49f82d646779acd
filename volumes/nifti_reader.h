/// @brief NIfTI-1 and NIfTI-2 (.nii, .nii.gz, .hdr/.img) reading through niftilib.
#pragma once

#include <string>

#include "volumes/volume.h"

namespace volumes {

/// Reads a 3D NIfTI volume (a 4D file with one time point is accepted). The grid comes from
/// the sform when its code is set, else the qform, else the voxel sizes alone (Analyze); the
/// NIfTI RAS+ world is converted to LPS by negating x and y. HU = stored * scl_slope +
/// scl_inter when scl_slope is non-zero. Throws VolumeError for unsupported data types,
/// sheared transforms, several volumes, truncated data or values that do not fit int16.
Volume readNifti(const std::string& path);

}  // namespace volumes
