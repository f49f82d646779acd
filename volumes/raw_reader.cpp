#include "volumes/raw_reader.h"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <vector>

namespace volumes {
namespace {

/// A description longer than this is not a raw-volume description.
constexpr std::size_t kMaxSpecBytes = 512;
/// Header bytes to skip are bounded so that skip + data size cannot overflow.
constexpr std::uint64_t kMaxSkipBytes = std::uint64_t{1} << 40;

[[noreturn]] void failSpec(const std::string& spec, const std::string& problem) {
    throw VolumeError("raw volume description '" + spec + "': " + problem +
                      " (expected e.g. 512x512x451:int16:0.7x0.7x1.25[:big][:skip=N])");
}

std::vector<std::string> split(const std::string& text, char separator) {
    std::vector<std::string> parts;
    std::size_t start = 0;
    while (true) {
        const std::size_t end = text.find(separator, start);
        parts.push_back(text.substr(start, end == std::string::npos ? std::string::npos : end - start));
        if (end == std::string::npos) break;
        start = end + 1;
    }
    return parts;
}

double parseNumber(const std::string& spec, const std::string& text, const std::string& what) {
    double value = 0.0;
    const char* end = text.data() + text.size();
    const auto result = std::from_chars(text.data(), end, value);
    if (text.empty() || result.ec != std::errc{} || result.ptr != end || !std::isfinite(value)) {
        failSpec(spec, what + " '" + text + "' is not a finite number");
    }
    return value;
}

}  // namespace

RawOptions parseRawSpec(const std::string& spec) {
    if (spec.size() > kMaxSpecBytes) failSpec(spec.substr(0, 40) + "...", "too long");
    const std::vector<std::string> parts = split(spec, ':');
    if (parts.size() < 3) failSpec(spec, "needs at least dims, type and spacing");
    RawOptions options;

    const std::vector<std::string> dims = split(parts[0], 'x');
    if (dims.size() != 3) failSpec(spec, "dims '" + parts[0] + "' are not NxNxN");
    for (int axis = 0; axis < 3; ++axis) {
        const std::string& text = dims[static_cast<std::size_t>(axis)];
        long long n = 0;
        const auto result = std::from_chars(text.data(), text.data() + text.size(), n);
        if (text.empty() || result.ec != std::errc{} || result.ptr != text.data() + text.size() || n < 1 ||
            n > kMaxDimension) {
            failSpec(spec, "size '" + text + "' along axis " + std::to_string(axis) + " is not an integer in 1.." +
                               std::to_string(kMaxDimension));
        }
        options.dims[static_cast<std::size_t>(axis)] = static_cast<int>(n);
    }

    static const std::map<std::string, ScalarType> kTypes = {
        {"int8", ScalarType::Int8},      {"uint8", ScalarType::UInt8},     {"int16", ScalarType::Int16},
        {"uint16", ScalarType::UInt16},  {"int32", ScalarType::Int32},     {"uint32", ScalarType::UInt32},
        {"float", ScalarType::Float32},  {"float32", ScalarType::Float32}, {"double", ScalarType::Float64},
        {"float64", ScalarType::Float64}};
    const auto type = kTypes.find(parts[1]);
    if (type == kTypes.end()) failSpec(spec, "unsupported type '" + parts[1] + "'");
    options.format.type = type->second;

    const std::vector<std::string> spacing = split(parts[2], 'x');
    if (spacing.size() != 3) failSpec(spec, "spacing '" + parts[2] + "' is not AxBxC (mm)");
    for (int axis = 0; axis < 3; ++axis) {
        const double s = parseNumber(spec, spacing[static_cast<std::size_t>(axis)], "spacing");
        if (s < kMinSpacingMm || s > kMaxSpacingMm) {
            failSpec(spec, "spacing " + spacing[static_cast<std::size_t>(axis)] + " mm is outside " +
                               std::to_string(kMinSpacingMm) + ".." + std::to_string(kMaxSpacingMm));
        }
        options.spacingMm[axis] = s;
    }

    for (std::size_t i = 3; i < parts.size(); ++i) {
        const std::string& part = parts[i];
        if (part == "big") {
            options.format.isBigEndian = true;
        } else if (part == "little") {
            options.format.isBigEndian = false;
        } else if (part.rfind("skip=", 0) == 0) {
            const std::string text = part.substr(5);
            std::uint64_t n = 0;
            const auto result = std::from_chars(text.data(), text.data() + text.size(), n);
            if (text.empty() || result.ec != std::errc{} || result.ptr != text.data() + text.size() ||
                n > kMaxSkipBytes) {
                failSpec(spec, "skip '" + text + "' is not a byte count up to 2^40");
            }
            options.headerBytes = n;
        } else if (part.rfind("slope=", 0) == 0) {
            options.format.slope = parseNumber(spec, part.substr(6), "slope");
            if (options.format.slope == 0.0) failSpec(spec, "slope must not be 0");
        } else if (part.rfind("intercept=", 0) == 0) {
            options.format.intercept = parseNumber(spec, part.substr(10), "intercept");
        } else {
            failSpec(spec, "unknown option '" + part + "'");
        }
    }
    return options;
}

Volume readRaw(const std::string& path, const RawOptions& options) {
    Volume volume;
    volume.dims = options.dims;
    volume.spacingMm = options.spacingMm;
    validateGeometry(volume, path);
    std::error_code error;
    const std::uintmax_t fileBytes = std::filesystem::file_size(path, error);
    if (error) throw VolumeError(path + ": cannot read file size (" + error.message() + ")");
    const std::uint64_t expected = options.headerBytes + volume.voxelCount() * bytesPerValue(options.format.type);
    if (fileBytes != expected) {
        throw VolumeError(path + ": file holds " + std::to_string(fileBytes) + " bytes, the raw description (" +
                          std::to_string(options.dims[0]) + "x" + std::to_string(options.dims[1]) + "x" +
                          std::to_string(options.dims[2]) + " " + scalarTypeName(options.format.type) + ", skip " +
                          std::to_string(options.headerBytes) + ") calls for " + std::to_string(expected));
    }
    std::ifstream in(path, std::ios::binary);
    if (!in) throw VolumeError(path + ": cannot open file (" + std::strerror(errno) + ")");
    in.seekg(static_cast<std::streamoff>(options.headerBytes));
    volume.hu.resize(volume.voxelCount());
    readRawHu(path, in, options.format, volume.hu);
    validateVolume(volume, path);
    return volume;
}

}  // namespace volumes
