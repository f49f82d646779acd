#include "volumes/metaimage_io.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <vector>

namespace volumes {
namespace {

/// A MetaImage header longer than this (or with more lines) is not a CT header.
constexpr std::size_t kMaxHeaderBytes = 1 << 16;
constexpr int kMaxHeaderLines = 256;

[[noreturn]] void fail(const std::string& source, const std::string& problem) {
    throw VolumeError(source + ": " + problem);
}

std::string trim(const std::string& s) {
    const auto first = s.find_first_not_of(" \t\r");
    if (first == std::string::npos) return {};
    const auto last = s.find_last_not_of(" \t\r");
    return s.substr(first, last - first + 1);
}

bool isTrue(const std::string& value) {
    std::string v = value;
    std::transform(v.begin(), v.end(), v.begin(), [](unsigned char c) { return std::tolower(c); });
    return v == "true" || v == "1";
}

/// Parses exactly `count` finite numbers from `value`, or fails naming `key`.
std::vector<double> parseNumbers(const std::string& source, const std::string& key, const std::string& value,
                                 std::size_t count) {
    std::istringstream in(value);
    std::vector<double> numbers;
    std::string token;
    while (numbers.size() <= count && in >> token) {
        std::istringstream number(token);
        double x = 0.0;
        std::string trailing;
        if (!(number >> x) || (number >> trailing) || !std::isfinite(x)) break;
        numbers.push_back(x);
    }
    if (numbers.size() != count || (in >> token)) {
        fail(source, key + " = '" + value + "', expected " + std::to_string(count) + " finite numbers");
    }
    return numbers;
}

ScalarType parseElementType(const std::string& source, const std::string& value) {
    static const std::map<std::string, ScalarType> kTypes = {
        {"MET_CHAR", ScalarType::Int8},     {"MET_UCHAR", ScalarType::UInt8},   {"MET_SHORT", ScalarType::Int16},
        {"MET_USHORT", ScalarType::UInt16}, {"MET_INT", ScalarType::Int32},     {"MET_UINT", ScalarType::UInt32},
        {"MET_FLOAT", ScalarType::Float32}, {"MET_DOUBLE", ScalarType::Float64}};
    const auto it = kTypes.find(value);
    if (it == kTypes.end()) {
        fail(source, "ElementType = '" + value +
                         "' is not supported (expected MET_CHAR, MET_UCHAR, MET_SHORT, MET_USHORT, "
                         "MET_INT, MET_UINT, MET_FLOAT or MET_DOUBLE)");
    }
    return it->second;
}

}  // namespace

MetaImageHeader parseMetaImageHeader(const std::string& source, std::istream& in) {
    MetaImageHeader header;
    bool hasDims = false, hasType = false, hasSpacing = false;
    std::uint64_t consumed = 0;
    std::string line;
    for (int lineCount = 0;; ++lineCount) {
        if (lineCount >= kMaxHeaderLines || consumed > kMaxHeaderBytes) {
            fail(source, "header has no ElementDataFile line within " + std::to_string(kMaxHeaderBytes) +
                             " bytes (not a MetaImage file?)");
        }
        if (!std::getline(in, line)) fail(source, "header ends before its ElementDataFile line");
        consumed += line.size() + 1;
        const std::string text = trim(line);
        if (text.empty()) continue;
        const auto equals = text.find('=');
        if (equals == std::string::npos) fail(source, "header line '" + text.substr(0, 80) + "' has no '='");
        const std::string key = trim(text.substr(0, equals));
        const std::string value = trim(text.substr(equals + 1));
        if (key == "ObjectType") {
            if (value != "Image") fail(source, "ObjectType = '" + value + "', expected Image");
        } else if (key == "NDims") {
            if (value != "3") fail(source, "NDims = '" + value + "', expected 3");
        } else if (key == "DimSize") {
            const auto n = parseNumbers(source, key, value, 3);
            for (int axis = 0; axis < 3; ++axis) {
                const double v = n[static_cast<std::size_t>(axis)];
                if (v != std::floor(v) || v < 1 || v > kMaxDimension) {
                    fail(source, "DimSize = '" + value + "', expected integers in 1.." + std::to_string(kMaxDimension));
                }
                header.dims[static_cast<std::size_t>(axis)] = static_cast<int>(v);
            }
            hasDims = true;
        } else if (key == "ElementSpacing" || (key == "ElementSize" && !hasSpacing)) {
            // ElementSize is the voxel's extent; it stands in for the spacing only when no
            // ElementSpacing is given.
            const auto s = parseNumbers(source, key, value, 3);
            header.spacingMm = {s[0], s[1], s[2]};
            hasSpacing = key == "ElementSpacing";
        } else if (key == "Offset" || key == "Position" || key == "Origin") {
            const auto o = parseNumbers(source, key, value, 3);
            header.originLps = {o[0], o[1], o[2]};
        } else if (key == "TransformMatrix" || key == "Rotation" || key == "Orientation") {
            // MetaIO lists the direction of grid axis 0 first, then axis 1, then axis 2.
            const auto m = parseNumbers(source, key, value, 9);
            for (int axis = 0; axis < 3; ++axis) {
                const std::size_t a = static_cast<std::size_t>(axis) * 3;
                header.directionLps[axis] = glm::dvec3(m[a], m[a + 1], m[a + 2]);
            }
        } else if (key == "ElementType") {
            header.format.type = parseElementType(source, value);
            hasType = true;
        } else if (key == "ElementByteOrderMSB" || key == "BinaryDataByteOrderMSB") {
            header.format.isBigEndian = isTrue(value);
        } else if (key == "CompressedData") {
            header.isCompressed = isTrue(value);
        } else if (key == "ElementNumberOfChannels") {
            if (value != "1") fail(source, "ElementNumberOfChannels = '" + value + "', expected 1 (CT is scalar)");
        } else if (key == "HeaderSize") {
            const auto h = parseNumbers(source, key, value, 1);
            if (h[0] != std::floor(h[0]) || h[0] < -1 || h[0] > 1e15) {
                fail(source, "HeaderSize = '" + value + "', expected -1 or a byte count");
            }
            header.headerBytes = static_cast<std::int64_t>(h[0]);
        } else if (key == "ElementDataFile") {
            if (value.empty()) fail(source, "ElementDataFile is empty");
            if (value.rfind("LIST", 0) == 0 || value.find('%') != std::string::npos ||
                value.find(' ') != std::string::npos) {
                fail(source, "ElementDataFile = '" + value +
                                 "': data split over several files is not supported (one file expected)");
            }
            header.dataFile = value;
            header.dataOffset = consumed;
            break;
        }
        // Other fields (AnatomicalOrientation, CenterOfRotation, ElementMin/Max, ...) do not
        // change how voxels map to LPS space, since ITK always writes LPS.
    }
    if (!hasDims) fail(source, "header lacks DimSize");
    if (!hasType) fail(source, "header lacks ElementType");
    return header;
}

Volume readMetaImage(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) fail(path, "cannot open file (" + std::string(std::strerror(errno)) + ")");
    const MetaImageHeader header = parseMetaImageHeader(path, in);

    Volume volume;
    volume.dims = header.dims;
    volume.spacingMm = header.spacingMm;
    volume.originLps = header.originLps;
    volume.directionLps = header.directionLps;
    validateGeometry(volume, path);

    // Open the data: after the header for LOCAL, else a file beside the header.
    std::string dataPath = path;
    std::ifstream separate;
    std::istream* data = &in;
    std::uint64_t dataBytesAvailable = 0;
    const std::uint64_t rawBytes = volume.voxelCount() * bytesPerValue(header.format.type);
    if (header.dataFile == "LOCAL") {
        if (header.headerBytes > 0) fail(path, "HeaderSize with ElementDataFile = LOCAL is not supported");
        dataBytesAvailable = std::filesystem::file_size(path) - header.dataOffset;
    } else {
        dataPath = (std::filesystem::path(path).parent_path() / header.dataFile).string();
        separate.open(dataPath, std::ios::binary);
        if (!separate) {
            fail(path, "cannot open its ElementDataFile '" + dataPath + "' (" + std::strerror(errno) + ")");
        }
        std::error_code error;
        const std::uint64_t fileBytes = std::filesystem::file_size(dataPath, error);
        if (error) fail(dataPath, "cannot read file size (" + error.message() + ")");
        std::uint64_t skip = 0;
        if (header.headerBytes == -1) {
            if (header.isCompressed) fail(path, "HeaderSize = -1 cannot be combined with CompressedData");
            if (fileBytes < rawBytes) {
                fail(dataPath, "holds " + std::to_string(fileBytes) + " bytes, fewer than the " +
                                   std::to_string(rawBytes) + " the header calls for");
            }
            skip = fileBytes - rawBytes;
        } else {
            skip = static_cast<std::uint64_t>(header.headerBytes);
        }
        if (skip > fileBytes) fail(dataPath, "HeaderSize exceeds the file size");
        separate.seekg(static_cast<std::streamoff>(skip));
        dataBytesAvailable = fileBytes - skip;
        data = &separate;
    }

    if (header.isCompressed) {
        volume.hu.resize(volume.voxelCount());  // compressed data cannot be sized before inflating
        readCompressedHu(dataPath, *data, header.format, volume.hu);
    } else {
        // Checked before the voxels are allocated: a short file whose header asks for 2 GiB
        // must be called truncated, not fail the allocation.
        if (dataBytesAvailable != rawBytes) {
            fail(dataPath, "holds " + std::to_string(dataBytesAvailable) +
                               " bytes of voxel data, the header's DimSize and ElementType call for " +
                               std::to_string(rawBytes) + (dataBytesAvailable < rawBytes ? " (truncated file?)" : ""));
        }
        volume.hu.resize(volume.voxelCount());
        readRawHu(dataPath, *data, header.format, volume.hu);
    }
    validateVolume(volume, path);
    return volume;
}

}  // namespace volumes
