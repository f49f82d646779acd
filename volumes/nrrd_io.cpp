#include "volumes/nrrd_io.h"

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <vector>

#include "volumes/gzip_compress.h"

namespace volumes {
namespace {

/// A header longer than this is not a CT volume's header.
constexpr std::size_t kMaxHeaderBytes = 1 << 20;

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

ScalarType parseType(const std::string& path, const std::string& value) {
    static const std::map<std::string, ScalarType> kTypes = {
        {"signed char", ScalarType::Int8},
        {"int8", ScalarType::Int8},
        {"int8_t", ScalarType::Int8},
        {"uchar", ScalarType::UInt8},
        {"unsigned char", ScalarType::UInt8},
        {"uint8", ScalarType::UInt8},
        {"uint8_t", ScalarType::UInt8},
        {"short", ScalarType::Int16},
        {"short int", ScalarType::Int16},
        {"signed short", ScalarType::Int16},
        {"signed short int", ScalarType::Int16},
        {"int16", ScalarType::Int16},
        {"int16_t", ScalarType::Int16},
        {"ushort", ScalarType::UInt16},
        {"unsigned short", ScalarType::UInt16},
        {"unsigned short int", ScalarType::UInt16},
        {"uint16", ScalarType::UInt16},
        {"uint16_t", ScalarType::UInt16},
        {"int", ScalarType::Int32},
        {"signed int", ScalarType::Int32},
        {"int32", ScalarType::Int32},
        {"int32_t", ScalarType::Int32},
        {"uint", ScalarType::UInt32},
        {"unsigned int", ScalarType::UInt32},
        {"uint32", ScalarType::UInt32},
        {"uint32_t", ScalarType::UInt32},
        {"float", ScalarType::Float32},
        {"double", ScalarType::Float64},
    };
    const auto it = kTypes.find(lower(value));
    if (it == kTypes.end()) fail(path, "unsupported NRRD type '" + value + "'");
    return it->second;
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

/// An integer field within [low, high], or fail naming it.
std::int64_t parseInteger(const std::string& path, const std::string& key, const std::string& value, std::int64_t low,
                          std::int64_t high) {
    std::istringstream in(value);
    long long n = 0;
    std::string rest;
    if (!(in >> n) || (in >> rest) || n < low || n > high) {
        fail(path, key + " '" + value + "' is not an integer in " + std::to_string(low) + ".." + std::to_string(high));
    }
    return n;
}

}  // namespace

NrrdHeader parseNrrdHeader(const std::string& path, std::istream& in) {
    NrrdHeader header;
    std::string line;
    if (!std::getline(in, line) || line.rfind("NRRD000", 0) != 0) {
        fail(path, "not a NRRD file (the first line must start with NRRD000)");
    }
    bool hasType = false, hasSizes = false, hasDimension = false;
    std::size_t headerBytes = line.size() + 1;
    while (true) {
        if (!std::getline(in, line)) {
            // A detached header may end at the end of the file instead of at a blank line.
            if (header.dataFile.empty()) fail(path, "header ends before the blank line that precedes the data");
            break;
        }
        headerBytes += line.size() + 1;
        if (headerBytes > kMaxHeaderBytes) fail(path, "header longer than 1 MiB");
        line = trim(line);
        if (line.empty()) break;  // a blank line ends the header
        if (line[0] == '#') continue;
        // "key: value" is a field; "key:=value" is a key/value pair we may ignore.
        if (line.find(":=") != std::string::npos) continue;
        const auto colon = line.find(": ");
        if (colon == std::string::npos) fail(path, "malformed header line '" + line.substr(0, 80) + "'");
        const std::string key = lower(trim(line.substr(0, colon)));
        const std::string value = trim(line.substr(colon + 2));
        if (key == "type") {
            header.type = parseType(path, value);
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
                    fail(path, "size " + std::to_string(n[axis]) + " along axis " + std::to_string(axis) +
                                   " is outside 1.." + std::to_string(kMaxDimension));
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
            const std::string endian = lower(value);
            if (endian != "big" && endian != "little") fail(path, "endian '" + value + "', expected little or big");
            header.isBigEndian = endian == "big";
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
            if (!parseVector(value, header.origin)) fail(path, "space origin '" + value + "' is not a 3-vector");
        } else if (key == "data file" || key == "datafile") {
            if (value.rfind("LIST", 0) == 0 || value.find('%') != std::string::npos ||
                value.find(' ') != std::string::npos) {
                fail(path, "data file '" + value + "': data split over several files is not supported");
            }
            header.dataFile = value;
        } else if (key == "byte skip" || key == "byteskip") {
            header.byteSkip = parseInteger(path, key, value, -1, std::numeric_limits<std::int32_t>::max());
        } else if (key == "line skip" || key == "lineskip") {
            header.lineSkip = parseInteger(path, key, value, 0, 1 << 20);
        }
    }
    if (!hasType || !hasSizes || !hasDimension) {
        fail(path, "header lacks one of the required fields type, dimension, sizes");
    }
    if (header.byteSkip == -1 && header.encoding != "raw") {
        fail(path, "byte skip -1 (data at the end of the file) needs raw encoding");
    }
    header.dataOffset = headerBytes;
    return header;
}

Volume readNrrd(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) fail(path, "cannot open file (" + std::string(std::strerror(errno)) + ")");
    const NrrdHeader header = parseNrrdHeader(path, in);

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
    validateGeometry(volume, path);

    // Where the data are: after the header, or in the detached file beside it.
    std::string dataPath = path;
    std::ifstream detached;
    std::istream* data = &in;
    std::uint64_t dataStart = header.dataOffset;
    if (!header.dataFile.empty()) {
        dataPath = (std::filesystem::path(path).parent_path() / header.dataFile).string();
        detached.open(dataPath, std::ios::binary);
        if (!detached) fail(path, "cannot open its data file '" + dataPath + "' (" + std::strerror(errno) + ")");
        data = &detached;
        dataStart = 0;
    }
    data->clear();
    data->seekg(static_cast<std::streamoff>(dataStart));
    std::string skipped;
    for (std::int64_t n = 0; n < header.lineSkip; ++n) {
        if (!std::getline(*data, skipped))
            fail(dataPath, "ends within the " + std::to_string(header.lineSkip) + " lines to skip");
    }
    std::error_code error;
    const std::uint64_t fileBytes = std::filesystem::file_size(dataPath, error);
    if (error) fail(dataPath, "cannot read file size (" + error.message() + ")");
    std::uint64_t position = static_cast<std::uint64_t>(static_cast<std::streamoff>(data->tellg()));
    const std::uint64_t expectedBytes = volume.voxelCount() * bytesPerValue(header.type);
    if (header.byteSkip == -1) {
        if (fileBytes < expectedBytes) {
            fail(dataPath, "holds " + std::to_string(fileBytes) + " bytes, fewer than the " +
                               std::to_string(expectedBytes) + " the header's sizes and type call for");
        }
        position = fileBytes - expectedBytes;
    } else {
        position += static_cast<std::uint64_t>(header.byteSkip);
    }
    if (position > fileBytes) fail(dataPath, "byte skip points past the end of the file");
    data->seekg(static_cast<std::streamoff>(position));

    StoredFormat format;
    format.type = header.type;
    format.isBigEndian = header.isBigEndian;
    if (header.encoding == "raw") {
        // Checked before the voxels are allocated: a 100-byte file whose header asks for 2 GiB
        // must be called truncated, not fail the allocation.
        const std::uint64_t availableBytes = fileBytes - position;
        if (availableBytes != expectedBytes) {
            fail(dataPath, "holds " + std::to_string(availableBytes) +
                               " bytes of voxel data, the header's sizes and type call for " +
                               std::to_string(expectedBytes) +
                               (availableBytes < expectedBytes ? " (truncated file?)" : ""));
        }
        volume.hu.resize(volume.voxelCount());
        readRawHu(dataPath, *data, format, volume.hu);
    } else {
        if (position >= fileBytes) fail(dataPath, "has no voxel data after the header");
        volume.hu.resize(volume.voxelCount());  // compressed data cannot be sized before inflating
        readCompressedHu(dataPath, *data, format, volume.hu);
    }
    validateVolume(volume, path);
    return volume;
}

namespace {

/// Opens `path` for a new NRRD file, refusing to replace one unless `overwrite`.
std::ofstream openNrrdForWriting(const std::string& path, bool overwrite) {
    if (!overwrite && std::filesystem::exists(path)) {
        fail(path, "exists already (pass --force to replace it)");
    }
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    if (!out) fail(path, "cannot open for writing (" + std::string(std::strerror(errno)) + ")");
    out.precision(17);
    return out;
}

/// The header lines that place `grid` in the patient frame (LPS): sizes, axes, origin.
void writeLpsGeometry(std::ostream& out, const Volume& grid) {
    out << "space: left-posterior-superior\n"
        << "sizes: " << grid.dims[0] << ' ' << grid.dims[1] << ' ' << grid.dims[2] << '\n'
        << "space directions:";
    for (int axis = 0; axis < 3; ++axis) {
        const glm::dvec3 d = grid.directionLps[axis] * grid.spacingMm[axis];
        out << " (" << d.x << ',' << d.y << ',' << d.z << ')';
    }
    out << "\nkinds: domain domain domain\n"
        << "space origin: (" << grid.originLps.x << ',' << grid.originLps.y << ',' << grid.originLps.z << ")\n";
}

}  // namespace

void writeNrrd(const Volume& volume, const std::string& path, bool overwrite) {
    validateVolume(volume, path);
    std::ofstream out = openNrrdForWriting(path, overwrite);
    out << "NRRD0004\n"
        << "# conformal-vc volume, int16 Hounsfield units\n"
        << "type: int16\n"
        << "dimension: 3\n";
    writeLpsGeometry(out, volume);
    out << "endian: little\n"
        << "encoding: raw\n\n";
    static_assert(std::endian::native == std::endian::little, "writer assumes a little-endian host");
    out.write(reinterpret_cast<const char*>(volume.hu.data()),
              static_cast<std::streamsize>(volume.hu.size() * sizeof(int16_t)));
    if (!out) fail(path, "write failed (disk full or folder not writable?)");
}

void writeLabelNrrd(const Volume& grid, std::span<const std::uint8_t> labels, const NrrdKeyValues& keyValues,
                    const std::string& path, bool overwrite) {
    if (labels.size() != grid.voxelCount()) {
        fail(path, "holds " + std::to_string(labels.size()) + " labels for a grid of " +
                       std::to_string(grid.voxelCount()) + " voxels");
    }
    for (const auto& [key, value] : keyValues) {
        const bool isOneLine = key.find_first_of("\n\r") == std::string::npos && value.find_first_of("\n\r") == std::string::npos;
        if (key.empty() || key.find(":=") != std::string::npos || !isOneLine) {
            fail(path, "key/value pair '" + key + "' cannot be written in a NRRD header");
        }
    }
    std::ofstream out = openNrrdForWriting(path, overwrite);
    out << "NRRD0004\n"
        << "# conformal-vc labels\n"
        << "type: uint8\n"
        << "dimension: 3\n";
    writeLpsGeometry(out, grid);
    out << "encoding: gzip\n";
    for (const auto& [key, value] : keyValues) out << key << ":=" << value << '\n';
    out << '\n';
    // Labels are long runs of one value: level 6 makes a whole CT's lumen a few hundred kB.
    const std::vector<unsigned char> payload = gzipCompressed(std::as_bytes(labels), 6);
    out.write(reinterpret_cast<const char*>(payload.data()), static_cast<std::streamsize>(payload.size()));
    if (!out) fail(path, "write failed (disk full or folder not writable?)");
}

}  // namespace volumes
