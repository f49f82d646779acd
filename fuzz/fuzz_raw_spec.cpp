/// @brief libFuzzer target: the raw-volume description parser (text from the command line)
/// and the colon phantom's polyp description parser.
#include <cstddef>
#include <cstdint>
#include <string>

#include "volumes/raw_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    try {
        const volumes::RawOptions options = volumes::parseRawSpec(text);
        // A description that parses must describe a sane grid.
        volumes::Volume grid;
        grid.dims = options.dims;
        grid.spacingMm = options.spacingMm;
        try {
            volumes::validateGeometry(grid, "fuzz");
        } catch (const volumes::VolumeError&) {
            // Only the voxel-count limit may reject what the parser accepted.
            const std::size_t voxels = static_cast<std::size_t>(grid.dims[0]) * grid.dims[1] * grid.dims[2];
            if (voxels <= volumes::kMaxVoxelCount) __builtin_trap();
        }
    } catch (const volumes::VolumeError&) {
        // Rejecting bad input with a VolumeError is the expected outcome.
    }
    return 0;
}
