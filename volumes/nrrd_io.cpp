#include "volumes/nrrd_io.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <vector>

#include <zlib.h>

namespace volumes {
namespace {

/// A header longer than this is not a CT volume's header.
constexpr std::size_t kMaxHeaderBytes = 1 << 20;

enum class ScalarType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

struct NrrdHeader {
    ScalarType type = ScalarType::Int16;
    std::size_t bytesPerValue = 2;
    std::array<int, 3> sizes{0, 0, 0};
    std::string encoding = "raw";
    bool isBigEndian = false;
    bool isRas = false;
    bool hasSpaceDirections = false;
    glm::dmat3 spaceDirections{1.0};
    glm::dvec3 spacings{1.0};
    glm::dvec3 origin{0.0};
    std::streamoff dataOffset = 0;
};

std::string trim(const std::string& s) {
    const auto first = s.find_first_not_of(" \t\r");
    if (first == std::string::npos) return {};
    const auto last = s.find_last_not_of(" \t\r");
    return s.substr(first, last - first + 1);
}

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
    return s;
}

[[noreturn]] void fail(const std::string& path, const std::string& problem) {
    throw VolumeError(path + ": " + problem);
}

ScalarType parseType(const std::string& path, const std::string& value, std::size_t& bytes) {
    static const std::map<std::string, std::pair<ScalarType, std::size_t>> kTypes = {
        {"signed char", {ScalarType::Int8, 1}},     {"int8", {ScalarType::Int8, 1}},
        {"int8_t", {ScalarType::Int8, 1}},          {"uchar", {ScalarType::UInt8, 1}},
        {"unsigned char", {ScalarType::UInt8, 1}},  {"uint8", {ScalarType::UInt8, 1}},
        {"uint8_t", {ScalarType::UInt8, 1}},        {"short", {ScalarType::Int16, 2}},
        {"short int", {ScalarType::Int16, 2}},      {"signed short", {ScalarType::Int16, 2}},
        {"signed short int", {ScalarType::Int16, 2}}, {"int16", {ScalarType::Int16, 2}},
        {"int16_t", {ScalarType::Int16, 2}},        {"ushort", {ScalarType::UInt16, 2}},
        {"unsigned short", {ScalarType::UInt16, 2}}, {"unsigned short int", {ScalarType::UInt16, 2}},
        {"uint16", {ScalarType::UInt16, 2}},        {"uint16_t", {ScalarType::UInt16, 2}},
        {"int", {ScalarType::Int32, 4}},            {"signed int", {ScalarType::Int32, 4}},
        {"int32", {ScalarType::Int32, 4}},          {"int32_t", {ScalarType::Int32, 4}},
        {"uint", {ScalarType::UInt32, 4}},          {"unsigned int", {ScalarType::UInt32, 4}},
        {"uint32", {ScalarType::UInt32, 4}},        {"uint32_t", {ScalarType::UInt32, 4}},
        {"float", {ScalarType::Float32, 4}},        {"double", {ScalarType::Float64, 8}},
    };
    const auto it = kTypes.find(lower(value));
    if (it == kTypes.end()) fail(path, "unsupported NRRD type '" + value + "'");
    bytes = it->second.second;
    return it->second.first;
}

/// Parses "(x,y,z)" into a vector; false when the text is not three finite numbers.
bool parseVector(const std::string& text, glm::dvec3& out) {
    std::string cleaned = text;
    for (char& c : cleaned) {
        if (c == '(' || c == ')' || c == ',') c = ' ';
    }
    std::istringstream in(cleaned);
    double x = 0, y = 0, z = 0;
    if (!(in >> x >> y >> z)) return false;
    std::string rest;
    if (in >> rest) return false;
    out = {x, y, z};
    return std::isfinite(x) && std::isfinite(y) && std::isfinite(z);
}

NrrdHeader parseHeader(const std::string& path, std::istream& in) {
    NrrdHeader header;
    std::string line;
    if (!std::getline(in, line) || line.rfind("NRRD000", 0) != 0) {
        fail(path, "not a NRRD file (the first line must start with NRRD000)");
    }
    bool hasType = false, hasSizes = false, hasDimension = false;
    std::size_t headerBytes = line.size();
    while (std::getline(in, line)) {
        headerBytes += line.size() + 1;
        if (headerBytes > kMaxHeaderBytes) fail(path, "header longer than 1 MiB");
        line = trim(line);
        if (line.empty()) break;  // a blank line ends the header
        if (line[0] == '#') continue;
        // "key: value" is a field; "key:=value" is a key/value pair we may ignore.
        if (line.find(":=") != std::string::npos) continue;
        const auto colon = line.find(": ");
        if (colon == std::string::npos) fail(path, "malformed header line '" + line + "'");
        const std::string key = lower(trim(line.substr(0, colon)));
        const std::string value = trim(line.substr(colon + 2));
        if (key == "type") {
            header.type = parseType(path, value, header.bytesPerValue);
            hasType = true;
        } else if (key == "dimension") {
            if (value != "3") fail(path, "dimension is " + value + ", expected 3");
            hasDimension = true;
        } else if (key == "sizes") {
            std::istringstream sizes(value);
            long long n[3] = {0, 0, 0};
            std::string extra;
            if (!(sizes >> n[0] >> n[1] >> n[2]) || (sizes >> extra)) {
                fail(path, "sizes '" + value + "' are not three integers");
            }
            for (int axis = 0; axis < 3; ++axis) {
                if (n[axis] < 1 || n[axis] > kMaxDimension) {
                    fail(path, "size " + std::to_string(n[axis]) + " along axis " +
                                   std::to_string(axis) + " is outside 1.." +
                                   std::to_string(kMaxDimension));
                }
                header.sizes[static_cast<std::size_t>(axis)] = static_cast<int>(n[axis]);
            }
            hasSizes = true;
        } else if (key == "encoding") {
            header.encoding = lower(value);
            if (header.encoding == "gz") header.encoding = "gzip";
            if (header.encoding != "raw" && header.encoding != "gzip") {
                fail(path, "unsupported encoding '" + value + "' (raw and gzip are supported)");
            }
        } else if (key == "endian") {
            header.isBigEndian = lower(value) == "big";
        } else if (key == "space") {
            const std::string space = lower(value);
            if (space == "right-anterior-superior" || space == "ras") {
                header.isRas = true;
            } else if (space != "left-posterior-superior" && space != "lps") {
                fail(path, "unsupported space '" + value + "' (LPS and RAS are supported)");
            }
        } else if (key == "space dimension") {
            if (value != "3") fail(path, "space dimension is " + value + ", expected 3");
        } else if (key == "space directions") {
            std::istringstream vectors(value);
            for (int axis = 0; axis < 3; ++axis) {
                std::string token;
                if (!(vectors >> token) || !parseVector(token, header.spaceDirections[axis])) {
                    fail(path, "space directions '" + value + "' are not three 3-vectors");
                }
            }
            header.hasSpaceDirections = true;
        } else if (key == "spacings") {
            std::istringstream in3(value);
            if (!(in3 >> header.spacings.x >> header.spacings.y >> header.spacings.z)) {
                fail(path, "spacings '" + value + "' are not three numbers");
            }
        } else if (key == "space origin") {
            if (!parseVector(value, header.origin)) {
                fail(path, "space origin '" + value + "' is not a 3-vector");
            }
        } else if (key == "data file" || key == "datafile") {
            fail(path, "detached NRRD data ('data file') is not supported by this reader");
        }
    }
    if (!hasType || !hasSizes || !hasDimension) {
        fail(path, "header lacks one of the required fields type, dimension, sizes");
    }
    header.dataOffset = static_cast<std::streamoff>(headerBytes + 1);
    return header;
}

std::vector<unsigned char> gunzip(const std::string& path, const std::vector<unsigned char>& packed,
                                  std::size_t expectedBytes) {
    std::vector<unsigned char> out(expectedBytes);
    z_stream stream{};
    if (inflateInit2(&stream, 15 + 32) != Z_OK) fail(path, "cannot start gzip decoder");
    stream.next_in = const_cast<unsigned char*>(packed.data());
    stream.avail_in = static_cast<uInt>(std::min<std::size_t>(packed.size(), std::numeric_limits<uInt>::max()));
    stream.next_out = out.data();
    stream.avail_out = static_cast<uInt>(std::min<std::size_t>(out.size(), std::numeric_limits<uInt>::max()));
    const int status = inflate(&stream, Z_FINISH);
    const std::size_t produced = stream.total_out;
    inflateEnd(&stream);
    if (status == Z_BUF_ERROR && produced == expectedBytes) {
        fail(path, "gzip data holds more than the " + std::to_string(expectedBytes) +
                       " bytes the header's sizes and type call for");
    }
    if (status != Z_STREAM_END) {
        fail(path, "gzip data is truncated or corrupt (decoded " + std::to_string(produced) +
                       " of " + std::to_string(expectedBytes) + " bytes)");
    }
    if (produced != expectedBytes) {
        fail(path, "gzip data decodes to " + std::to_string(produced) + " bytes, the header calls for " +
                       std::to_string(expectedBytes));
    }
    return out;
}

template <typename T>
T loadValue(const unsigned char* bytes, bool isBigEndian) {
    unsigned char buffer[sizeof(T)];
    std::memcpy(buffer, bytes, sizeof(T));
    if (isBigEndian != (std::endian::native == std::endian::big)) std::reverse(buffer, buffer + sizeof(T));
    T value;
    std::memcpy(&value, buffer, sizeof(T));
    return value;
}

/// Converts one stored value to int16 HU; throws for values that are not finite or do not fit.
int16_t huFromStored(const std::string& path, double value, std::size_t index) {
    if (!std::isfinite(value)) {
        fail(path, "voxel " + std::to_string(index) + " is not a finite number");
    }
    const double rounded = std::nearbyint(value);
    if (rounded < std::numeric_limits<int16_t>::min() || rounded > std::numeric_limits<int16_t>::max()) {
        fail(path, "voxel " + std::to_string(index) + " has value " + std::to_string(value) +
                       ", outside the int16 Hounsfield range");
    }
    return static_cast<int16_t>(rounded);
}

void convertToHu(const std::string& path, const NrrdHeader& header, const unsigned char* data,
                 std::vector<int16_t>& hu) {
    const std::size_t n = hu.size();
    const std::size_t step = header.bytesPerValue;
    for (std::size_t i = 0; i < n; ++i) {
        const unsigned char* p = data + i * step;
        double value = 0.0;
        switch (header.type) {
            case ScalarType::Int8: value = static_cast<int8_t>(p[0]); break;
            case ScalarType::UInt8: value = p[0]; break;
            case ScalarType::Int16: hu[i] = loadValue<int16_t>(p, header.isBigEndian); continue;
            case ScalarType::UInt16: value = loadValue<uint16_t>(p, header.isBigEndian); break;
            case ScalarType::Int32: value = loadValue<int32_t>(p, header.isBigEndian); break;
            case ScalarType::UInt32: value = loadValue<uint32_t>(p, header.isBigEndian); break;
            case ScalarType::Float32: value = loadValue<float>(p, header.isBigEndian); break;
            case ScalarType::Float64: value = loadValue<double>(p, header.isBigEndian); break;
        }
        hu[i] = huFromStored(path, value, i);
    }
}

}  // namespace

Volume readNrrd(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) fail(path, "cannot open file (" + std::string(std::strerror(errno)) + ")");
    const NrrdHeader header = parseHeader(path, in);

    Volume volume;
    volume.dims = header.sizes;
    if (header.hasSpaceDirections) {
        for (int axis = 0; axis < 3; ++axis) {
            const glm::dvec3 column = header.spaceDirections[axis];
            const double length = glm::length(column);
            volume.spacingMm[axis] = length;
            volume.directionLps[axis] = length > 0.0 ? column / length : column;
        }
    } else {
        volume.spacingMm = header.spacings;
    }
    volume.originLps = header.origin;
    if (header.isRas) {
        // RAS -> LPS: negate the first two patient coordinates.
        const glm::dmat3 flip(glm::dvec3(-1, 0, 0), glm::dvec3(0, -1, 0), glm::dvec3(0, 0, 1));
        volume.directionLps = flip * volume.directionLps;
        volume.originLps = flip * volume.originLps;
    }
    volume.hu.resize(volume.voxelCount());
    validateVolume(volume, path);

    const std::size_t expectedBytes = volume.voxelCount() * header.bytesPerValue;
    in.clear();
    in.seekg(0, std::ios::end);
    const std::streamoff fileBytes = in.tellg();
    const std::streamoff availableBytes = fileBytes - header.dataOffset;
    in.seekg(header.dataOffset);

    if (header.encoding == "raw") {
        if (availableBytes < 0 || static_cast<std::size_t>(availableBytes) != expectedBytes) {
            fail(path, "holds " + std::to_string(std::max<std::streamoff>(availableBytes, 0)) +
                           " bytes of voxel data, the header's sizes and type call for " +
                           std::to_string(expectedBytes) + (availableBytes < static_cast<std::streamoff>(expectedBytes)
                                                                 ? " (truncated file?)"
                                                                 : ""));
        }
        if (header.type == ScalarType::Int16 && !header.isBigEndian && std::endian::native == std::endian::little) {
            // The common case reads straight into the volume: no second copy in memory.
            in.read(reinterpret_cast<char*>(volume.hu.data()), static_cast<std::streamsize>(expectedBytes));
            if (!in) fail(path, "read error in voxel data");
        } else {
            std::vector<unsigned char> raw(expectedBytes);
            in.read(reinterpret_cast<char*>(raw.data()), static_cast<std::streamsize>(expectedBytes));
            if (!in) fail(path, "read error in voxel data");
            convertToHu(path, header, raw.data(), volume.hu);
        }
    } else {
        if (availableBytes <= 0) fail(path, "has no voxel data after the header");
        std::vector<unsigned char> packed(static_cast<std::size_t>(availableBytes));
        in.read(reinterpret_cast<char*>(packed.data()), availableBytes);
        if (!in) fail(path, "read error in voxel data");
        const std::vector<unsigned char> raw = gunzip(path, packed, expectedBytes);
        convertToHu(path, header, raw.data(), volume.hu);
    }
    return volume;
}

void writeNrrd(const Volume& volume, const std::string& path, bool overwrite) {
    validateVolume(volume, path);
    if (!overwrite && std::filesystem::exists(path)) {
        fail(path, "exists already (pass --force to replace it)");
    }
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    if (!out) fail(path, "cannot open for writing (" + std::string(std::strerror(errno)) + ")");
    out.precision(17);
    out << "NRRD0004\n"
        << "# conformal-vc volume, int16 Hounsfield units\n"
        << "type: int16\n"
        << "dimension: 3\n"
        << "space: left-posterior-superior\n"
        << "sizes: " << volume.dims[0] << ' ' << volume.dims[1] << ' ' << volume.dims[2] << '\n'
        << "space directions:";
    for (int axis = 0; axis < 3; ++axis) {
        const glm::dvec3 d = volume.directionLps[axis] * volume.spacingMm[axis];
        out << " (" << d.x << ',' << d.y << ',' << d.z << ')';
    }
    out << "\nkinds: domain domain domain\n"
        << "endian: little\n"
        << "encoding: raw\n"
        << "space origin: (" << volume.originLps.x << ',' << volume.originLps.y << ','
        << volume.originLps.z << ")\n\n";
    static_assert(std::endian::native == std::endian::little, "writer assumes a little-endian host");
    out.write(reinterpret_cast<const char*>(volume.hu.data()),
              static_cast<std::streamsize>(volume.hu.size() * sizeof(int16_t)));
    if (!out) fail(path, "write failed (disk full or folder not writable?)");
}

}  // namespace volumes
