/// @brief libFuzzer target: the NRRD header parser and the voxel decoding it drives (raw and
/// gzip), on arbitrary bytes held in memory.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "volumes/nrrd_io.h"
#include "volumes/voxel_decode.h"

namespace {

/// Volumes larger than this are parsed but not decoded, so one input cannot exhaust memory.
constexpr std::size_t kMaxFuzzVoxels = std::size_t{1} << 16;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    const std::string bytes(reinterpret_cast<const char*>(data), size);
    std::istringstream in(bytes);
    try {
        const volumes::NrrdHeader header = volumes::parseNrrdHeader("fuzz.nrrd", in);
        const std::size_t voxels = static_cast<std::size_t>(header.sizes[0]) * header.sizes[1] * header.sizes[2];
        if (voxels > kMaxFuzzVoxels || !header.dataFile.empty()) return 0;
        in.clear();
        in.seekg(static_cast<std::streamoff>(header.dataOffset));
        volumes::StoredFormat format;
        format.type = header.type;
        format.isBigEndian = header.isBigEndian;
        std::vector<int16_t> hu(voxels);
        if (header.encoding == "gzip") {
            volumes::readCompressedHu("fuzz.nrrd", in, format, hu);
        } else {
            volumes::readRawHu("fuzz.nrrd", in, format, hu);
        }
    } catch (const volumes::VolumeError&) {
        // Rejecting bad input with a VolumeError is the expected outcome.
    }
    return 0;
}
