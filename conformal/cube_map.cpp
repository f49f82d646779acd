/// @brief Cube-map conventions (Vulkan), file I/O with header checks, CPU bilinear sampling.
#include "conformal/cube_map.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <fstream>

#include <glm/geometric.hpp>

namespace conformal {

namespace {

constexpr char kMagic[8] = {'C', 'V', 'C', 'C', 'U', 'B', 'E', '\0'};
/// Version 2 records the missing walls where version 1 held a reserved 0; a version-1 file is a
/// map for a display without its ceiling, and still loads as one.
constexpr std::uint32_t kVersion = 2;
constexpr std::uint32_t kCeilingOnlyVersion = 1;
constexpr int kMaxSize = 16384;

struct FileHeader {
    char magic[8];
    std::uint32_t version;
    std::uint32_t size;
    std::uint32_t kind;
    std::uint32_t missingFaces;  ///< bit f: face f (Vulkan order) is missing; reserved 0 in version 1
    double boxSize[3];
    double mapCentre[3];
    std::uint64_t inputHash;
    std::uint64_t payloadBytes;
};
static_assert(sizeof(FileHeader) == 88, "the header has no padding");

std::uint64_t payloadBytesFor(std::uint64_t size) { return 6 * size * size * 4 * sizeof(float); }

}  // namespace

std::string mapKindName(MapKind kind) {
    switch (kind) {
        case MapKind::Conformal: return "conformal";
        case MapKind::Linear: return "linear";
        case MapKind::None: return "none";
    }
    return "unknown map kind " + std::to_string(static_cast<std::uint32_t>(kind));
}

MapKind mapKindFromName(const std::string& name) {
    for (MapKind kind : {MapKind::Conformal, MapKind::Linear, MapKind::None}) {
        if (mapKindName(kind) == name) return kind;
    }
    throw std::invalid_argument("unknown map '" + name + "' (conformal, linear, none)");
}

glm::dvec3 directionFromCubeFace(int face, double s, double t) {
    const double sc = 2.0 * s - 1.0;
    const double tc = 2.0 * t - 1.0;
    glm::dvec3 d(0.0);
    switch (face) {
        case 0: d = {1.0, -tc, -sc}; break;
        case 1: d = {-1.0, -tc, sc}; break;
        case 2: d = {sc, 1.0, tc}; break;
        case 3: d = {sc, -1.0, -tc}; break;
        case 4: d = {sc, -tc, 1.0}; break;
        default: d = {-sc, -tc, -1.0}; break;
    }
    return glm::normalize(d);
}

CubeFaceCoordinate cubeFaceFromDirection(const glm::dvec3& d) {
    const glm::dvec3 a = glm::abs(d);
    CubeFaceCoordinate c;
    double sc = 0.0;
    double tc = 0.0;
    double ma = 0.0;
    if (a.x >= a.y && a.x >= a.z) {
        ma = a.x;
        c.face = d.x >= 0.0 ? 0 : 1;
        sc = d.x >= 0.0 ? -d.z : d.z;
        tc = -d.y;
    } else if (a.y >= a.z) {
        ma = a.y;
        c.face = d.y >= 0.0 ? 2 : 3;
        sc = d.x;
        tc = d.y >= 0.0 ? d.z : -d.z;
    } else {
        ma = a.z;
        c.face = d.z >= 0.0 ? 4 : 5;
        sc = d.z >= 0.0 ? d.x : -d.x;
        tc = -d.y;
    }
    c.s = 0.5 * (sc / ma + 1.0);
    c.t = 0.5 * (tc / ma + 1.0);
    return c;
}

glm::vec4 sampleCubeMapBilinear(const CubeMap& map, const glm::dvec3& direction) {
    const CubeFaceCoordinate c = cubeFaceFromDirection(direction);
    const int n = map.size;
    const double x = c.s * n - 0.5;
    const double y = c.t * n - 0.5;
    const int i0 = static_cast<int>(std::floor(x));
    const int j0 = static_cast<int>(std::floor(y));
    const double fx = x - i0;
    const double fy = y - j0;
    auto tap = [&](int i, int j) {
        int face = c.face;
        if (i < 0 || j < 0 || i >= n || j >= n) {
            // Seamless filtering: the tap's centre continues the face's plane onto a neighbour.
            const glm::dvec3 beyond = directionFromCubeFace(face, (i + 0.5) / n, (j + 0.5) / n);
            const CubeFaceCoordinate other = cubeFaceFromDirection(beyond);
            face = other.face;
            i = std::clamp(static_cast<int>(std::floor(other.s * n)), 0, n - 1);
            j = std::clamp(static_cast<int>(std::floor(other.t * n)), 0, n - 1);
        }
        const float* p = &map.rgba[map.texelIndex(face, i, j)];
        return glm::dvec4(p[0], p[1], p[2], p[3]);
    };
    const glm::dvec4 value = (1.0 - fy) * ((1.0 - fx) * tap(i0, j0) + fx * tap(i0 + 1, j0)) +
                             fy * ((1.0 - fx) * tap(i0, j0 + 1) + fx * tap(i0 + 1, j0 + 1));
    return glm::vec4(value);
}

void saveCubeMap(const CubeMap& map, const std::filesystem::path& path) {
    const std::uint64_t payload = payloadBytesFor(static_cast<std::uint64_t>(map.size));
    if (map.size <= 0 || map.rgba.size() * sizeof(float) != payload) {
        throw CubeMapFileError("cube map '" + path.string() + "': refusing to write " +
                               std::to_string(map.rgba.size()) + " floats for size " +
                               std::to_string(map.size));
    }
    if (map.kind != MapKind::Conformal && map.kind != MapKind::Linear) {
        throw CubeMapFileError("cube map '" + path.string() + "': refusing to write a map of kind " +
                               mapKindName(map.kind) + " (only conformal and linear maps are baked)");
    }
    FileHeader header{};
    std::memcpy(header.magic, kMagic, sizeof(kMagic));
    header.version = kVersion;
    header.size = static_cast<std::uint32_t>(map.size);
    header.kind = static_cast<std::uint32_t>(map.kind);
    for (int a = 0; a < 3; ++a) {
        header.boxSize[a] = map.box.size[a];
        header.mapCentre[a] = map.box.mapCentre[a];
    }
    header.missingFaces = map.box.missingFaces;
    header.inputHash = map.inputHash;
    header.payloadBytes = payload;
    // Write beside the target and rename, so a reader never sees a half-written file.
    std::filesystem::path partial = path;
    partial += ".partial";
    {
        std::ofstream out(partial, std::ios::binary | std::ios::trunc);
        if (!out) throw CubeMapFileError("cube map '" + path.string() + "': cannot open for writing");
        out.write(reinterpret_cast<const char*>(&header), sizeof(header));
        out.write(reinterpret_cast<const char*>(map.rgba.data()), static_cast<std::streamsize>(payload));
        if (!out) throw CubeMapFileError("cube map '" + path.string() + "': write failed");
    }
    std::filesystem::rename(partial, path);
}

CubeMap loadCubeMap(const std::filesystem::path& path) {
    const std::string name = "cube map '" + path.string() + "': ";
    std::ifstream in(path, std::ios::binary);
    if (!in) throw CubeMapFileError(name + "cannot open the file");
    FileHeader header{};
    in.read(reinterpret_cast<char*>(&header), sizeof(header));
    if (in.gcount() != static_cast<std::streamsize>(sizeof(header))) {
        throw CubeMapFileError(name + "truncated header (" + std::to_string(in.gcount()) + " of " +
                               std::to_string(sizeof(header)) + " bytes)");
    }
    if (std::memcmp(header.magic, kMagic, sizeof(kMagic)) != 0) {
        throw CubeMapFileError(name + "wrong magic; not a conformal-vc cube map");
    }
    if (header.version != kVersion && header.version != kCeilingOnlyVersion) {
        throw CubeMapFileError(name + "unsupported version " + std::to_string(header.version) +
                               " (expected " + std::to_string(kCeilingOnlyVersion) + " or " +
                               std::to_string(kVersion) + ")");
    }
    if (header.size == 0 || header.size > kMaxSize) {
        throw CubeMapFileError(name + "face size " + std::to_string(header.size) +
                               " is outside [1, " + std::to_string(kMaxSize) + "]");
    }
    // Kind None means "nothing to bake": a file that claims it is as malformed as an unknown kind.
    if (header.kind != static_cast<std::uint32_t>(MapKind::Conformal) &&
        header.kind != static_cast<std::uint32_t>(MapKind::Linear)) {
        throw CubeMapFileError(name + "map kind " + std::to_string(header.kind) +
                               " is not a baked map (0 conformal or 1 linear)");
    }
    const std::uint64_t payload = payloadBytesFor(header.size);
    if (header.payloadBytes != payload) {
        throw CubeMapFileError(name + "payload of " + std::to_string(header.payloadBytes) +
                               " bytes does not match face size " + std::to_string(header.size) +
                               " (expected " + std::to_string(payload) + ")");
    }
    CubeMap map;
    map.size = static_cast<int>(header.size);
    map.kind = static_cast<MapKind>(header.kind);
    for (int a = 0; a < 3; ++a) {
        map.box.size[a] = header.boxSize[a];
        map.box.mapCentre[a] = header.mapCentre[a];
    }
    map.box.missingFaces = header.version == kCeilingOnlyVersion ? faceBit(kCeilingFace) : header.missingFaces;
    map.inputHash = header.inputHash;
    try {
        validateCaveBox(map.box);
    } catch (const std::invalid_argument& error) {
        throw CubeMapFileError(name + "bad box in the header: " + error.what());
    }
    // The header alone can claim up to 25 GiB of texels: compare with what the file holds
    // before allocating, so a short file is refused instead of exhausting memory.
    in.seekg(0, std::ios::end);
    const std::streamoff fileBytes = in.tellg();
    in.seekg(static_cast<std::streamoff>(sizeof(header)), std::ios::beg);
    if (fileBytes < 0 || !in) throw CubeMapFileError(name + "cannot determine the file's size");
    const std::uint64_t texelBytes = static_cast<std::uint64_t>(fileBytes) - sizeof(header);
    if (texelBytes < payload) {
        throw CubeMapFileError(name + "truncated texel data (" + std::to_string(texelBytes) + " of " +
                               std::to_string(payload) + " bytes)");
    }
    if (texelBytes > payload) throw CubeMapFileError(name + "unexpected bytes after the texel data");
    map.rgba.resize(payload / sizeof(float));
    in.read(reinterpret_cast<char*>(map.rgba.data()), static_cast<std::streamsize>(payload));
    if (static_cast<std::uint64_t>(in.gcount()) != payload) {
        throw CubeMapFileError(name + "truncated texel data (" + std::to_string(in.gcount()) +
                               " of " + std::to_string(payload) + " bytes)");
    }
    // A NaN or infinite texel would bend rays into NaN directions far from the file that caused it.
    const auto bad = std::find_if(map.rgba.begin(), map.rgba.end(), [](float v) { return !std::isfinite(v); });
    if (bad != map.rgba.end()) {
        const std::size_t index = static_cast<std::size_t>(bad - map.rgba.begin());
        throw CubeMapFileError(name + "texel data hold a non-finite value (float " + std::to_string(index) + " of " +
                               std::to_string(map.rgba.size()) + ")");
    }
    return map;
}

}  // namespace conformal
