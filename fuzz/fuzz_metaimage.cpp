/// @brief libFuzzer target: the MetaImage header parser and the voxel decoding it drives (raw
/// and zlib), on arbitrary bytes held in memory.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "volumes/metaimage_io.h"
#include "volumes/voxel_decode.h"

namespace {

/// Volumes larger than this are parsed but not decoded, so one input cannot exhaust memory.
constexpr std::size_t kMaxFuzzVoxels = std::size_t{1} << 16;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    const std::string bytes(reinterpret_cast<const char*>(data), size);
    std::istringstream in(bytes);
    try {
        const volumes::MetaImageHeader header = volumes::parseMetaImageHeader("fuzz.mha", in);
        const std::size_t voxels = static_cast<std::size_t>(header.dims[0]) * header.dims[1] * header.dims[2];
        if (voxels > kMaxFuzzVoxels || header.dataFile != "LOCAL") return 0;
        std::vector<int16_t> hu(voxels);
        if (header.isCompressed) {
            volumes::readCompressedHu("fuzz.mha", in, header.format, hu);
        } else {
            volumes::readRawHu("fuzz.mha", in, header.format, hu);
        }
    } catch (const volumes::VolumeError&) {
        // Rejecting bad input with a VolumeError is the expected outcome.
    }
    return 0;
}
