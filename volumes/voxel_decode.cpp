#include "volumes/voxel_decode.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include <zlib.h>

namespace volumes {
namespace {

/// Conversion works on chunks of this many bytes: large enough to amortise the stream calls,
/// small beside a CT volume (a multiple of every value size).
constexpr std::size_t kChunkBytes = std::size_t{1} << 20;

template <typename T>
T loadValue(const unsigned char* bytes, bool isSwapped) {
    unsigned char buffer[sizeof(T)];
    std::memcpy(buffer, bytes, sizeof(T));
    if (isSwapped) std::reverse(buffer, buffer + sizeof(T));
    T value;
    std::memcpy(&value, buffer, sizeof(T));
    return value;
}

[[noreturn]] void failValue(const std::string& source, std::size_t index, double value) {
    const std::string what = std::isfinite(value)
                                 ? "has value " + std::to_string(value) + " HU, outside the int16 range"
                                 : "is not a finite number (NaN or Inf)";
    throw VolumeError(source + ": voxel " + std::to_string(index) + " " + what);
}

template <typename T>
void convertTyped(const std::string& source, const StoredFormat& format, const unsigned char* bytes,
                  std::span<int16_t> hu, std::size_t firstIndex) {
    const bool isSwapped = format.isBigEndian != (std::endian::native == std::endian::big);
    const bool isIdentity = format.slope == 1.0 && format.intercept == 0.0;
    if constexpr (std::is_same_v<T, int16_t>) {
        if (isIdentity && !isSwapped) {
            std::memcpy(hu.data(), bytes, hu.size() * sizeof(int16_t));
            return;
        }
    }
    constexpr double kLow = std::numeric_limits<int16_t>::min();
    constexpr double kHigh = std::numeric_limits<int16_t>::max();
    for (std::size_t i = 0; i < hu.size(); ++i) {
        const double stored = static_cast<double>(loadValue<T>(bytes + i * sizeof(T), isSwapped));
        const double value = isIdentity ? stored : stored * format.slope + format.intercept;
        // NaN fails both comparisons, so test for the good case.
        const double rounded = std::nearbyint(value);
        if (!(rounded >= kLow && rounded <= kHigh)) failValue(source, firstIndex + i, value);
        hu[i] = static_cast<int16_t>(rounded);
    }
}

}  // namespace

std::size_t bytesPerValue(ScalarType type) {
    switch (type) {
        case ScalarType::Int8:
        case ScalarType::UInt8: return 1;
        case ScalarType::Int16:
        case ScalarType::UInt16: return 2;
        case ScalarType::Int32:
        case ScalarType::UInt32:
        case ScalarType::Float32: return 4;
        case ScalarType::Float64: return 8;
    }
    return 0;
}

std::string scalarTypeName(ScalarType type) {
    switch (type) {
        case ScalarType::Int8: return "int8";
        case ScalarType::UInt8: return "uint8";
        case ScalarType::Int16: return "int16";
        case ScalarType::UInt16: return "uint16";
        case ScalarType::Int32: return "int32";
        case ScalarType::UInt32: return "uint32";
        case ScalarType::Float32: return "float";
        case ScalarType::Float64: return "double";
    }
    return "unknown";
}

void huFromStored(const std::string& source, const StoredFormat& format, const unsigned char* bytes,
                  std::span<int16_t> hu, std::size_t firstIndex) {
    if (!std::isfinite(format.slope) || !std::isfinite(format.intercept) || format.slope == 0.0) {
        throw VolumeError(source + ": rescale slope " + std::to_string(format.slope) + " / intercept " +
                          std::to_string(format.intercept) +
                          " are not usable (expected finite numbers, slope non-zero)");
    }
    switch (format.type) {
        case ScalarType::Int8: convertTyped<int8_t>(source, format, bytes, hu, firstIndex); break;
        case ScalarType::UInt8: convertTyped<uint8_t>(source, format, bytes, hu, firstIndex); break;
        case ScalarType::Int16: convertTyped<int16_t>(source, format, bytes, hu, firstIndex); break;
        case ScalarType::UInt16: convertTyped<uint16_t>(source, format, bytes, hu, firstIndex); break;
        case ScalarType::Int32: convertTyped<int32_t>(source, format, bytes, hu, firstIndex); break;
        case ScalarType::UInt32: convertTyped<uint32_t>(source, format, bytes, hu, firstIndex); break;
        case ScalarType::Float32: convertTyped<float>(source, format, bytes, hu, firstIndex); break;
        case ScalarType::Float64: convertTyped<double>(source, format, bytes, hu, firstIndex); break;
    }
}

void readRawHu(const std::string& source, std::istream& in, const StoredFormat& format, std::span<int16_t> hu) {
    const std::size_t valueBytes = bytesPerValue(format.type);
    const std::size_t valuesPerChunk = kChunkBytes / valueBytes;
    std::vector<unsigned char> chunk(std::min(hu.size(), valuesPerChunk) * valueBytes);
    for (std::size_t first = 0; first < hu.size(); first += valuesPerChunk) {
        const std::size_t count = std::min(valuesPerChunk, hu.size() - first);
        in.read(reinterpret_cast<char*>(chunk.data()), static_cast<std::streamsize>(count * valueBytes));
        const auto got = static_cast<std::size_t>(in.gcount());
        if (got != count * valueBytes) {
            throw VolumeError(source + ": voxel data is truncated: holds " + std::to_string(first * valueBytes + got) +
                              " bytes, expected " + std::to_string(hu.size() * valueBytes));
        }
        huFromStored(source, format, chunk.data(), hu.subspan(first, count), first);
    }
}

void readCompressedHu(const std::string& source, std::istream& in, const StoredFormat& format, std::span<int16_t> hu) {
    const std::size_t valueBytes = bytesPerValue(format.type);
    const std::size_t valuesPerChunk = kChunkBytes / valueBytes;
    const std::size_t expectedBytes = hu.size() * valueBytes;
    std::vector<unsigned char> packed(std::size_t{1} << 18);
    std::vector<unsigned char> chunk(std::min(hu.size(), valuesPerChunk) * valueBytes);

    z_stream stream{};
    // 15 + 32: the largest window, and accept either a zlib or a gzip header.
    if (inflateInit2(&stream, 15 + 32) != Z_OK) throw VolumeError(source + ": cannot start zlib");
    struct InflateGuard {
        z_stream* s;
        ~InflateGuard() { inflateEnd(s); }
    } guard{&stream};

    bool isStreamEnd = false;
    auto inflateInto = [&](unsigned char* out, std::size_t bytes) -> std::size_t {
        stream.next_out = out;
        stream.avail_out = static_cast<uInt>(bytes);
        while (stream.avail_out > 0 && !isStreamEnd) {
            if (stream.avail_in == 0) {
                in.read(reinterpret_cast<char*>(packed.data()), static_cast<std::streamsize>(packed.size()));
                stream.next_in = packed.data();
                stream.avail_in = static_cast<uInt>(in.gcount());
                if (stream.avail_in == 0) break;  // no more input
            }
            const int status = inflate(&stream, Z_NO_FLUSH);
            if (status == Z_STREAM_END) {
                isStreamEnd = true;
            } else if (status != Z_OK && status != Z_BUF_ERROR) {
                throw VolumeError(source + ": compressed voxel data is corrupt (zlib: " +
                                  std::string(stream.msg ? stream.msg : "error " + std::to_string(status)) + ")");
            }
        }
        return bytes - stream.avail_out;
    };

    for (std::size_t first = 0; first < hu.size(); first += valuesPerChunk) {
        const std::size_t count = std::min(valuesPerChunk, hu.size() - first);
        const std::size_t got = inflateInto(chunk.data(), count * valueBytes);
        if (got != count * valueBytes) {
            throw VolumeError(source + ": compressed voxel data is truncated: decodes to " +
                              std::to_string(first * valueBytes + got) + " bytes, expected " +
                              std::to_string(expectedBytes));
        }
        huFromStored(source, format, chunk.data(), hu.subspan(first, count), first);
    }
    unsigned char extra[16];
    if (inflateInto(extra, sizeof(extra)) > 0) {
        throw VolumeError(source + ": compressed voxel data holds more than the " + std::to_string(expectedBytes) +
                          " bytes the header calls for");
    }
}

}  // namespace volumes
