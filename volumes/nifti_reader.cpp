#include "volumes/nifti_reader.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <vector>

// niftilib's znz file handle differs with and without zlib; Debian builds it with zlib.
#ifndef HAVE_ZLIB
#define HAVE_ZLIB 1
#endif
#include <nifti2_io.h>

#include "volumes/nifti_header_check.h"
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

}  // namespace

Volume readNifti(const std::string& path) {
    nifti_set_debug_level(0);
    NiftiImagePtr image(nifti_image_read(path.c_str(), 0));
    if (!image)
        fail(path, "niftilib cannot read it as a NIfTI-1 or NIfTI-2 file (missing, not NIfTI, or corrupt header)");

    // The values niftilib parsed, checked and turned into a layout by our own rules.
    NiftiHeaderValues header;
    header.ndim = image->ndim;
    header.dim = {image->nx, image->ny, image->nz, image->nt, image->nu, image->nv, image->nw};
    header.datatype = image->datatype;
    header.datatypeName = nifti_datatype_string(image->datatype);
    header.bytesPerVoxel = image->nbyper;
    header.isBigEndian = image->byteorder == kNiftiMsbFirst;
    header.sclSlope = image->scl_slope;
    header.sclInter = image->scl_inter;
    header.qformCode = image->qform_code;
    header.sformCode = image->sform_code;
    for (std::size_t row = 0; row < 4; ++row) {
        for (std::size_t col = 0; col < 4; ++col) {
            header.qtoXyz[row][col] = image->qto_xyz.m[row][col];
            header.stoXyz[row][col] = image->sto_xyz.m[row][col];
        }
    }
    header.pixdim = {image->dx, image->dy, image->dz};
    header.dataOffset = image->iname_offset;
    const std::string dataPath = image->iname ? image->iname : path;
    const bool isCompressed = nifti_is_gzfile(dataPath.c_str()) != 0;
    std::error_code sizeError;
    const std::uintmax_t dataFileBytes = std::filesystem::file_size(dataPath, sizeError);
    if (!isCompressed && !sizeError) header.dataFileBytes = static_cast<int64_t>(dataFileBytes);
    const NiftiLayout layout = niftiLayout(header, path);
    const StoredFormat& format = layout.format;
    Volume volume = layout.grid;

    // Voxels: streamed through znzlib (plain or gzip) in chunks.
    std::unique_ptr<znzptr, ZnzCloser> file(znzopen(dataPath.c_str(), "rb", isCompressed ? 1 : 0));
    if (!file) fail(dataPath, "cannot open the image data");
    if (znzseek(file.get(), static_cast<znz_off_t>(layout.dataOffset), SEEK_SET) < 0) {
        fail(dataPath, "cannot seek to the image data at byte " + std::to_string(layout.dataOffset));
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
