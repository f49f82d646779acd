/// @brief Checks of the NIfTI header values and the layout derived from them (nifti_header_check.h).
#include "volumes/nifti_header_check.h"

#include <cmath>

#include <glm/glm.hpp>

namespace volumes {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& problem) {
    throw VolumeError(path + ": " + problem);
}

/// NIfTI DT_* codes (nifti1.h), spelled out so that this file needs no niftilib header.
ScalarType scalarTypeFromNifti(const NiftiHeaderValues& header, const std::string& path) {
    switch (header.datatype) {
        case 256: return ScalarType::Int8;     // DT_INT8
        case 2: return ScalarType::UInt8;      // DT_UINT8
        case 4: return ScalarType::Int16;      // DT_INT16
        case 512: return ScalarType::UInt16;   // DT_UINT16
        case 8: return ScalarType::Int32;      // DT_INT32
        case 768: return ScalarType::UInt32;   // DT_UINT32
        case 16: return ScalarType::Float32;   // DT_FLOAT32
        case 64: return ScalarType::Float64;   // DT_FLOAT64
        default: break;
    }
    fail(path, "NIfTI datatype " + header.datatypeName + " (" + std::to_string(header.datatype) +
                   ") is not supported (expected an 8, 16 or 32-bit integer, float32 or float64 scalar)");
}

/// The voxel-to-RAS affine the header selects: sform when its code is set, else qform, else
/// (Analyze) the voxel sizes alone.
void rasAffine(const NiftiHeaderValues& header, glm::dmat3& linear, glm::dvec3& offset) {
    const std::array<std::array<double, 4>, 4>* m = nullptr;
    if (header.sformCode > 0) {
        m = &header.stoXyz;
    } else if (header.qformCode > 0) {
        m = &header.qtoXyz;
    }
    offset = glm::dvec3(0.0);
    if (m == nullptr) {
        linear = glm::dmat3(glm::dvec3(std::abs(header.pixdim[0]), 0, 0), glm::dvec3(0, std::abs(header.pixdim[1]), 0),
                            glm::dvec3(0, 0, std::abs(header.pixdim[2])));
        return;
    }
    for (int col = 0; col < 3; ++col) {
        const auto c = static_cast<std::size_t>(col);
        linear[col] = glm::dvec3((*m)[0][c], (*m)[1][c], (*m)[2][c]);
    }
    offset = glm::dvec3((*m)[0][3], (*m)[1][3], (*m)[2][3]);
}

}  // namespace

NiftiLayout niftiLayout(const NiftiHeaderValues& header, const std::string& path) {
    // Shape: three spatial axes, no more than one volume.
    const auto& dim = header.dim;
    if (dim[0] < 1 || dim[1] < 1 || dim[2] < 1 || dim[0] > kMaxDimension || dim[1] > kMaxDimension ||
        dim[2] > kMaxDimension) {
        fail(path, "dim = " + std::to_string(dim[0]) + " " + std::to_string(dim[1]) + " " + std::to_string(dim[2]) +
                       ", expected sizes in 1.." + std::to_string(kMaxDimension));
    }
    // Each extra dimension on its own: their product can exceed (and wrap) 64 bits.
    if (header.ndim > 3 && (dim[3] > 1 || dim[4] > 1 || dim[5] > 1 || dim[6] > 1)) {
        fail(path, "holds more than one volume (dim[4..7] = " + std::to_string(dim[3]) + " " + std::to_string(dim[4]) +
                       " " + std::to_string(dim[5]) + " " + std::to_string(dim[6]) + "), expected one 3D CT volume");
    }
    NiftiLayout layout;
    layout.format.type = scalarTypeFromNifti(header, path);
    if (header.bytesPerVoxel < 0 || static_cast<std::size_t>(header.bytesPerVoxel) != bytesPerValue(layout.format.type)) {
        fail(path, "bitpix disagrees with datatype " + header.datatypeName);
    }
    layout.format.isBigEndian = header.isBigEndian;
    if (std::isfinite(header.sclSlope) && header.sclSlope != 0.0) {
        layout.format.slope = header.sclSlope;
        layout.format.intercept = std::isfinite(header.sclInter) ? header.sclInter : 0.0;
    }

    // Grid: columns of the affine are the axes; their lengths the spacing.
    glm::dmat3 ras(1.0);
    glm::dvec3 rasOffset(0.0);
    rasAffine(header, ras, rasOffset);
    const glm::dmat3 lpsFromRas(glm::dvec3(-1, 0, 0), glm::dvec3(0, -1, 0), glm::dvec3(0, 0, 1));
    Volume& grid = layout.grid;
    grid.dims = {static_cast<int>(dim[0]), static_cast<int>(dim[1]), static_cast<int>(dim[2])};
    for (int axis = 0; axis < 3; ++axis) {
        const glm::dvec3 column = lpsFromRas * ras[axis];
        const double length = glm::length(column);
        grid.spacingMm[axis] = length;
        grid.directionLps[axis] = length > 0.0 && std::isfinite(length) ? column / length : column;
    }
    grid.originLps = lpsFromRas * rasOffset;
    validateGeometry(grid, path);
    for (int a = 0; a < 3; ++a) {
        for (int b = a + 1; b < 3; ++b) {
            const double cosine = glm::dot(grid.directionLps[a], grid.directionLps[b]);
            if (std::abs(cosine) > 1e-3) {
                fail(path, "the " + std::string(header.sformCode > 0 ? "sform" : "qform") + " shears the grid (axes " +
                               std::to_string(a) + " and " + std::to_string(b) + " have cosine " +
                               std::to_string(cosine) + ", expected orthogonal axes)");
            }
        }
    }

    // Bytes: validateGeometry bounds the voxel count, so this product cannot overflow.
    if (header.dataOffset < 0) fail(path, "vox_offset " + std::to_string(header.dataOffset) + " is negative");
    layout.dataOffset = static_cast<uint64_t>(header.dataOffset);
    layout.dataBytes = static_cast<uint64_t>(grid.voxelCount()) * bytesPerValue(layout.format.type);
    if (header.dataFileBytes >= 0) {
        const auto fileBytes = static_cast<uint64_t>(header.dataFileBytes);
        const uint64_t held = fileBytes > layout.dataOffset ? fileBytes - layout.dataOffset : 0;
        if (held < layout.dataBytes) {
            fail(path, "image data is truncated: holds " + std::to_string(held) + " bytes after offset " +
                           std::to_string(layout.dataOffset) + ", dim and datatype call for " +
                           std::to_string(layout.dataBytes));
        }
    }
    return layout;
}

}  // namespace volumes
