/// @brief libFuzzer target: our checks of the NIfTI header values niftilib hands the reader
/// (volumes/nifti_header_check.h: dims, datatype and bitpix, scaling, qform/sform, pixdim, the
/// data offset and the byte count the file must hold), and the HU scaling of the few voxels
/// that follow. niftilib itself is not the target: the input is the values it would hand us.
///
/// Input layout, little-endian, missing bytes read as zero: int64 ndim, int64 dim[7] (nx..nw),
/// int32 datatype, int32 nbyper, uint8 byte order (bit 0: big-endian), float64 scl_slope,
/// float64 scl_inter, int32 qform_code, int32 sform_code, float64 qto_xyz[4][4], float64
/// sto_xyz[4][4] (row major), float64 pixdim[3], int64 vox_offset, int64 data file bytes
/// (-1: compressed, unknown), then stored voxel bytes.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "fuzz/fuzz_input_reader.h"
#include "volumes/nifti_header_check.h"

namespace {

using Reader = fuzz::InputReader;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    Reader in(data, size);
    volumes::NiftiHeaderValues header;
    header.ndim = in.next<int64_t>();
    for (int64_t& d : header.dim) d = in.next<int64_t>();
    header.datatype = in.next<int32_t>();
    header.datatypeName = "fuzzed";
    header.bytesPerVoxel = in.next<int32_t>();
    header.isBigEndian = (in.next<uint8_t>() & 1) != 0;
    header.sclSlope = in.next<double>();
    header.sclInter = in.next<double>();
    header.qformCode = in.next<int32_t>();
    header.sformCode = in.next<int32_t>();
    for (auto& row : header.qtoXyz) {
        for (double& v : row) v = in.next<double>();
    }
    for (auto& row : header.stoXyz) {
        for (double& v : row) v = in.next<double>();
    }
    for (double& v : header.pixdim) v = in.next<double>();
    header.dataOffset = in.next<int64_t>();
    header.dataFileBytes = in.next<int64_t>();

    volumes::NiftiLayout layout;
    try {
        layout = volumes::niftiLayout(header, "fuzz.nii");
    } catch (const volumes::VolumeError&) {
        return 0;  // refusing a bad header with a VolumeError is the expected outcome
    }
    // An accepted header describes a grid within the limits, and bytes the file holds.
    const std::size_t voxels = layout.grid.voxelCount();
    if (voxels == 0 || voxels > volumes::kMaxVoxelCount) __builtin_trap();
    if (layout.dataBytes != voxels * volumes::bytesPerValue(layout.format.type)) __builtin_trap();
    if (header.dataFileBytes >= 0 &&
        (layout.dataOffset > static_cast<uint64_t>(header.dataFileBytes) ||
         static_cast<uint64_t>(header.dataFileBytes) - layout.dataOffset < layout.dataBytes)) {
        __builtin_trap();
    }

    // The voxels that follow, scaled as the reader would scale them.
    const std::size_t valueBytes = volumes::bytesPerValue(layout.format.type);
    const std::size_t count = std::min(voxels, in.restSize() / valueBytes);
    if (count == 0) return 0;
    std::vector<int16_t> hu(count);
    try {
        volumes::huFromStored("fuzz.nii", layout.format, in.rest(), hu);
    } catch (const volumes::VolumeError&) {
        // A value that is not finite or does not fit int16 after scaling is refused.
    }
    return 0;
}
