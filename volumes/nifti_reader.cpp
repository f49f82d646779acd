#include "volumes/nifti_reader.h"

#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

// niftilib's znz file handle differs with and without zlib; Debian builds it with zlib.
#ifndef HAVE_ZLIB
#define HAVE_ZLIB 1
#endif
#include <nifti2_io.h>

#include "volumes/voxel_decode.h"

namespace volumes {
namespace {

/// niftilib's code for big-endian data in nifti_image::byteorder (its MSB_FIRST macro is
/// private to the library).
constexpr int kNiftiMsbFirst = 2;

/// Voxels are read and converted in chunks of this many bytes.
constexpr std::size_t kChunkBytes = std::size_t{1} << 20;

[[noreturn]] void fail(const std::string& path, const std::string& problem) {
    throw VolumeError(path + ": " + problem);
}

struct NiftiImageDeleter {
    void operator()(nifti_image* image) const { nifti_image_free(image); }
};
using NiftiImagePtr = std::unique_ptr<nifti_image, NiftiImageDeleter>;

struct ZnzCloser {
    void operator()(znzptr* file) const {
        znzFile f = file;
        znzclose(f);
    }
};

ScalarType scalarTypeFromNifti(const std::string& path, int datatype) {
    switch (datatype) {
        case DT_INT8: return ScalarType::Int8;
        case DT_UINT8: return ScalarType::UInt8;
        case DT_INT16: return ScalarType::Int16;
        case DT_UINT16: return ScalarType::UInt16;
        case DT_INT32: return ScalarType::Int32;
        case DT_UINT32: return ScalarType::UInt32;
        case DT_FLOAT32: return ScalarType::Float32;
        case DT_FLOAT64: return ScalarType::Float64;
        default: break;
    }
    fail(path, std::string("NIfTI datatype ") + nifti_datatype_string(datatype) + " (" + std::to_string(datatype) +
                   ") is not supported (expected an 8, 16 or 32-bit integer, float32 or float64 scalar)");
}

/// The voxel-to-world affine niftilib derived, as the columns and offset of a RAS transform.
struct RasAffine {
    glm::dmat3 linear{1.0};
    glm::dvec3 offset{0.0};
};

RasAffine affineOf(const nifti_image& image) {
    RasAffine affine;
    const nifti_dmat44* m = nullptr;
    if (image.sform_code > 0) {
        m = &image.sto_xyz;
    } else if (image.qform_code > 0) {
        m = &image.qto_xyz;
    }
    if (m == nullptr) {
        // Analyze-style: only voxel sizes are known.
        affine.linear = glm::dmat3(glm::dvec3(std::abs(image.dx), 0, 0), glm::dvec3(0, std::abs(image.dy), 0),
                                   glm::dvec3(0, 0, std::abs(image.dz)));
        return affine;
    }
    for (int col = 0; col < 3; ++col) {
        affine.linear[col] = glm::dvec3(m->m[0][col], m->m[1][col], m->m[2][col]);
    }
    affine.offset = glm::dvec3(m->m[0][3], m->m[1][3], m->m[2][3]);
    return affine;
}

}  // namespace

Volume readNifti(const std::string& path) {
    nifti_set_debug_level(0);
    NiftiImagePtr image(nifti_image_read(path.c_str(), 0));
    if (!image)
        fail(path, "niftilib cannot read it as a NIfTI-1 or NIfTI-2 file (missing, not NIfTI, or corrupt header)");

    // Shape: three spatial axes, no more than one volume.
    if (image->nx < 1 || image->ny < 1 || image->nz < 1 || image->nx > kMaxDimension || image->ny > kMaxDimension ||
        image->nz > kMaxDimension) {
        fail(path, "dim = " + std::to_string(image->nx) + " " + std::to_string(image->ny) + " " +
                       std::to_string(image->nz) + ", expected sizes in 1.." + std::to_string(kMaxDimension));
    }
    const int64_t extra = std::max<int64_t>(image->nt, 1) * std::max<int64_t>(image->nu, 1) *
                          std::max<int64_t>(image->nv, 1) * std::max<int64_t>(image->nw, 1);
    if (image->ndim > 3 && extra != 1) {
        fail(path, "holds " + std::to_string(extra) + " volumes (dim[4..7]), expected one 3D CT volume");
    }
    StoredFormat format;
    format.type = scalarTypeFromNifti(path, image->datatype);
    if (static_cast<std::size_t>(image->nbyper) != bytesPerValue(format.type)) {
        fail(path, "bitpix disagrees with datatype " + std::string(nifti_datatype_string(image->datatype)));
    }
    format.isBigEndian = image->byteorder == kNiftiMsbFirst;
    if (std::isfinite(image->scl_slope) && image->scl_slope != 0.0) {
        format.slope = image->scl_slope;
        format.intercept = std::isfinite(image->scl_inter) ? image->scl_inter : 0.0;
    }

    // Grid: columns of the affine are the axes; their lengths the spacing.
    const RasAffine ras = affineOf(*image);
    const glm::dmat3 lpsFromRas(glm::dvec3(-1, 0, 0), glm::dvec3(0, -1, 0), glm::dvec3(0, 0, 1));
    Volume volume;
    volume.dims = {static_cast<int>(image->nx), static_cast<int>(image->ny), static_cast<int>(image->nz)};
    for (int axis = 0; axis < 3; ++axis) {
        const glm::dvec3 column = lpsFromRas * ras.linear[axis];
        const double length = glm::length(column);
        volume.spacingMm[axis] = length;
        volume.directionLps[axis] = length > 0.0 && std::isfinite(length) ? column / length : column;
    }
    volume.originLps = lpsFromRas * ras.offset;
    validateGeometry(volume, path);
    for (int a = 0; a < 3; ++a) {
        for (int b = a + 1; b < 3; ++b) {
            const double cosine = glm::dot(volume.directionLps[a], volume.directionLps[b]);
            if (std::abs(cosine) > 1e-3) {
                fail(path, "the " + std::string(image->sform_code > 0 ? "sform" : "qform") + " shears the grid (axes " +
                               std::to_string(a) + " and " + std::to_string(b) + " have cosine " +
                               std::to_string(cosine) + ", expected orthogonal axes)");
            }
        }
    }

    // Voxels: streamed through znzlib (plain or gzip) in chunks.
    const std::string dataPath = image->iname ? image->iname : path;
    std::unique_ptr<znzptr, ZnzCloser> file(znzopen(dataPath.c_str(), "rb", nifti_is_gzfile(dataPath.c_str())));
    if (!file) fail(dataPath, "cannot open the image data");
    if (znzseek(file.get(), static_cast<znz_off_t>(image->iname_offset), SEEK_SET) < 0) {
        fail(dataPath, "cannot seek to the image data at byte " + std::to_string(image->iname_offset));
    }
    volume.hu.resize(volume.voxelCount());
    const std::size_t valueBytes = bytesPerValue(format.type);
    const std::size_t valuesPerChunk = kChunkBytes / valueBytes;
    std::vector<unsigned char> chunk(std::min(volume.hu.size(), valuesPerChunk) * valueBytes);
    for (std::size_t first = 0; first < volume.hu.size(); first += valuesPerChunk) {
        const std::size_t count = std::min(valuesPerChunk, volume.hu.size() - first);
        const std::size_t got = znzread(chunk.data(), 1, count * valueBytes, file.get());
        if (got != count * valueBytes) {
            fail(dataPath, "image data is truncated: holds " + std::to_string(first * valueBytes + got) +
                               " bytes, dim and datatype call for " + std::to_string(volume.hu.size() * valueBytes));
        }
        huFromStored(dataPath, format, chunk.data(), std::span<int16_t>(volume.hu).subspan(first, count), first);
    }
    validateVolume(volume, path);
    return volume;
}

}  // namespace volumes
