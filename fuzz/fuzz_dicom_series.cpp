/// @brief libFuzzer target: our checks of the values GDCM hands the DICOM reader
/// (volumes/dicom_series_check.h): the series grid from the first image and the slice positions
/// and orientations, each slice's size, spacing, pixel format, rescale values and decoded byte
/// count, and the bit masking and HU scaling of a few stored values. GDCM itself is not the
/// target: the input is the values it would hand us.
///
/// Input layout, little-endian, missing bytes read as zero: the first image's values, a uint8
/// slice count (at most 64), per slice float64 position[3] and orientation[6], a second image's
/// values (checked as one slice of the series), then stored pixel bytes. An image's values:
/// uint8 number of dimensions, uint32 dims[3], float64 spacing[3], uint16 samples per pixel,
/// uint8 scalar type (0..7: int8, uint8, int16, uint16, int32, uint32, float32, float64; other:
/// unsupported), uint8 bits stored, float64 slope, float64 intercept, uint64 decoded bytes.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "fuzz/fuzz_input_reader.h"
#include "volumes/dicom_series_check.h"

namespace {

using Reader = fuzz::InputReader;

volumes::DicomImageValues imageValues(Reader& in) {
    volumes::DicomImageValues image;
    image.numberOfDimensions = in.next<uint8_t>();
    for (unsigned& d : image.dims) d = in.next<uint32_t>();
    for (double& s : image.spacingMm) s = in.next<double>();
    image.samplesPerPixel = in.next<uint16_t>();
    const uint8_t type = in.next<uint8_t>();
    if (type < 8) image.type = static_cast<volumes::ScalarType>(type);
    image.typeName = "fuzzed";
    image.bitsStored = in.next<uint8_t>();
    image.slope = in.next<double>();
    image.intercept = in.next<double>();
    image.bufferBytes = static_cast<std::size_t>(in.next<uint64_t>());
    return image;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    // The pixel bytes are masked in place: work on a copy, libFuzzer's input is read-only.
    std::vector<uint8_t> bytes(data, data + size);
    Reader in(bytes.data(), bytes.size());
    const volumes::DicomImageValues first = imageValues(in);
    const std::size_t sliceCount = std::min<std::size_t>(in.next<uint8_t>(), 64);
    std::vector<volumes::DicomSlice> slices(sliceCount);
    for (std::size_t k = 0; k < sliceCount; ++k) {
        slices[k].path = "slice" + std::to_string(k) + ".dcm";
        slices[k].positionLps = in.vec3();
        slices[k].rowLps = in.vec3();
        slices[k].columnLps = in.vec3();
    }
    const volumes::DicomImageValues other = imageValues(in);

    volumes::Volume grid;
    try {
        grid = volumes::dicomSeriesGrid("fuzz", first, slices);
    } catch (const volumes::VolumeError&) {
        return 0;  // refusing a bad series with a VolumeError is the expected outcome
    }
    // An accepted series is one grid within the limits, its slices in order along the normal.
    if (grid.voxelCount() == 0 || grid.voxelCount() > volumes::kMaxVoxelCount) __builtin_trap();
    if (static_cast<std::size_t>(grid.dims[2]) != slices.size()) __builtin_trap();
    for (std::size_t k = 1; k < slices.size(); ++k) {
        if (!(slices[k - 1].distanceMm < slices[k].distanceMm)) __builtin_trap();
    }

    volumes::StoredFormat format;
    try {
        format = volumes::dicomSliceFormat("other.dcm", grid, other);
    } catch (const volumes::VolumeError&) {
        return 0;
    }
    const std::size_t sliceBytes = static_cast<std::size_t>(grid.dims[0]) * static_cast<std::size_t>(grid.dims[1]) *
                                   volumes::bytesPerValue(format.type);
    if (other.bufferBytes != sliceBytes) __builtin_trap();

    // The pixel bytes that follow, masked and scaled as the reader would.
    const std::size_t valueBytes = volumes::bytesPerValue(format.type);
    const std::size_t count = std::min(sliceBytes, in.restSize()) / valueBytes;
    const std::span<unsigned char> pixels(bytes.data() + (bytes.size() - in.restSize()), count * valueBytes);
    if (count == 0) return 0;
    volumes::maskStoredBits(other.bitsStored, format.type, pixels);
    std::vector<int16_t> hu(count);
    try {
        volumes::huFromStored("other.dcm", format, pixels.data(), hu);
    } catch (const volumes::VolumeError&) {
        // A value that is not finite or does not fit int16 after scaling is refused.
    }
    return 0;
}
