/// @brief The checks the NIfTI reader applies to the header values niftilib hands it, and the
/// grid, stored format and byte counts it derives from them. Pure (no niftilib), so the same
/// function serves the reader and its fuzz target.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "volumes/volume.h"
#include "volumes/voxel_decode.h"

namespace volumes {

/// The fields of niftilib's nifti_image that the reader uses, as niftilib parsed them.
struct NiftiHeaderValues {
    int64_t ndim = 3;
    std::array<int64_t, 7> dim{1, 1, 1, 1, 1, 1, 1};  ///< nx, ny, nz, nt, nu, nv, nw
    int datatype = 0;                                 ///< a NIfTI DT_* code
    std::string datatypeName;                         ///< niftilib's name for it, for messages
    int bytesPerVoxel = 0;                            ///< nbyper
    bool isBigEndian = false;
    double sclSlope = 0.0;
    double sclInter = 0.0;
    int qformCode = 0;
    int sformCode = 0;
    std::array<std::array<double, 4>, 4> qtoXyz{};  ///< qform voxel-to-RAS, row major
    std::array<std::array<double, 4>, 4> stoXyz{};  ///< sform voxel-to-RAS, row major
    std::array<double, 3> pixdim{1.0, 1.0, 1.0};    ///< dx, dy, dz (used when neither form is set)
    int64_t dataOffset = 0;                         ///< iname_offset: where the voxels start
    /// Bytes in the file that holds the voxels when it is not compressed; -1 when unknown (gzip).
    int64_t dataFileBytes = -1;
};

/// What the reader needs to read the voxels.
struct NiftiLayout {
    Volume grid;          ///< dims, spacing, origin and directions in LPS; no voxels
    StoredFormat format;  ///< type, byte order and the HU scaling
    uint64_t dataOffset = 0;
    uint64_t dataBytes = 0;  ///< voxel count times bytes per voxel
};

/// Checks `header` and derives the layout: one 3D volume (a 4D file with one time point is
/// accepted), a supported scalar type whose size agrees with nbyper, the grid from the sform
/// when its code is set, else the qform, else the voxel sizes (RAS+ converted to LPS by negating
/// x and y), axes that are orthogonal, a non-negative data offset and, when the data file's
/// size is known, at least dataBytes after it. HU = stored * scl_slope + scl_inter when
/// scl_slope is finite and non-zero. Throws VolumeError naming `path` and the value.
NiftiLayout niftiLayout(const NiftiHeaderValues& header, const std::string& path);

}  // namespace volumes
