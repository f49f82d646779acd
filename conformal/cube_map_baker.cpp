/// @brief Cube-map baking over all cores, the local-scale channel, and the on-disk cache.
#include "conformal/cube_map_baker.h"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <future>
#include <iomanip>
#include <sstream>
#include <thread>
#include <vector>

#include <glm/geometric.hpp>

#include "conformal/distortion.h"
#include "conformal/linear_map.h"
#include "conformal/parallel_for.h"

namespace conformal {

namespace {

/// Bumped whenever the map's construction or the bake changes, so old cache files miss.
// 2: the Riemann map's hole fill keeps clear of the boundary, and extrapolated boundary values
// are put back on the unit circle (cached bakes of version 1 are rebuilt).
constexpr const char* kAlgorithmVersion = "conformal-vc bake 3";
constexpr int kMaxBakeSize = 8192;

/// MapKind::None asks for no bending, so there is no map to bake: refuse it before any work.
void requireBakeableKind(MapKind kind) {
    if (kind != MapKind::Conformal && kind != MapKind::Linear) {
        throw std::invalid_argument("cube-map bake: map kind " + mapKindName(kind) +
                                    " has nothing to bake (conformal or linear)");
    }
}

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

std::uint64_t bakeInputHash(const BakeSettings& settings) {
    std::ostringstream text;
    text << std::setprecision(17) << kAlgorithmVersion << '|' << settings.size << '|'
         << static_cast<int>(settings.kind) << '|' << settings.box.size.x << ',' << settings.box.size.y
         << ',' << settings.box.size.z << '|' << settings.box.mapCentre.x << ','
         << settings.box.mapCentre.y << ',' << settings.box.mapCentre.z << '|' << settings.box.missingFaces;
    if (settings.kind == MapKind::Conformal) {
        text << '|' << settings.mesh.resolution << '|' << settings.mesh.grading << '|'
             << static_cast<int>(settings.flow.metric) << '|' << settings.flow.tolerance;
    }
    std::uint64_t hash = 14695981039346656037ull;
    for (const unsigned char c : text.str()) {
        hash ^= c;
        hash *= 1099511628211ull;
    }
    return hash;
}

CubeMap bakeCubeMap(const DirectionMap& map, const CaveBox& box, MapKind kind, int size) {
    requireBakeableKind(kind);
    if (size < 2 || size > kMaxBakeSize) {
        throw std::invalid_argument("cube-map bake: size " + std::to_string(size) +
                                    " is outside [2, " + std::to_string(kMaxBakeSize) + "]");
    }
    CubeMap cube;
    cube.size = size;
    cube.box = box;
    cube.kind = kind;
    cube.rgba.assign(static_cast<std::size_t>(6) * size * size * 4, 0.0f);
    // Scene directions in double first, so that the scale channel's differences are exact.
    std::vector<glm::dvec3> scene(static_cast<std::size_t>(6) * size * size);
    auto index = [size](int face, int i, int j) {
        return (static_cast<std::size_t>(face) * size + j) * size + i;
    };
    parallelFor(6 * size, [&](int row) {
        const int face = row / size;
        const int j = row % size;
        for (int i = 0; i < size; ++i) {
            const glm::dvec3 d = directionFromCubeFace(face, (i + 0.5) / size, (j + 0.5) / size);
            scene[index(face, i, j)] = map.sceneFromDisplay(d);
        }
    });
    parallelFor(6 * size, [&](int row) {
        const int face = row / size;
        const int j = row % size;
        const int j0 = std::max(j - 1, 0), j1 = std::min(j + 1, size - 1);
        for (int i = 0; i < size; ++i) {
            const int i0 = std::max(i - 1, 0), i1 = std::min(i + 1, size - 1);
            const auto dirAt = [&](int a, int b) {
                return directionFromCubeFace(face, (a + 0.5) / size, (b + 0.5) / size);
            };
            const MapJacobian jac = jacobianFromDifferences(
                dirAt(i, j), (dirAt(i1, j) - dirAt(i0, j)) / double(i1 - i0),
                (dirAt(i, j1) - dirAt(i, j0)) / double(j1 - j0), scene[index(face, i, j)],
                (scene[index(face, i1, j)] - scene[index(face, i0, j)]) / double(i1 - i0),
                (scene[index(face, i, j1)] - scene[index(face, i, j0)]) / double(j1 - j0));
            float* out = &cube.rgba[4 * index(face, i, j)];
            const glm::dvec3& s = scene[index(face, i, j)];
            out[0] = static_cast<float>(s.x);
            out[1] = static_cast<float>(s.y);
            out[2] = static_cast<float>(s.z);
            out[3] = static_cast<float>(jac.scale);
        }
    });
    return cube;
}

CubeMap bakeCubeMap(const BakeSettings& settings, BakeReport* report) {
    requireBakeableKind(settings.kind);
    validateCaveBox(settings.box);
    const auto start = std::chrono::steady_clock::now();
    CubeMap cube;
    double mapSeconds = 0.0;
    if (settings.kind == MapKind::Conformal) {
        const ConformalMap map({settings.box, settings.mesh, settings.flow});
        mapSeconds = secondsSince(start);
        cube = bakeCubeMap(map, settings.box, settings.kind, settings.size);
    } else {
        const LinearMap map(settings.box);
        cube = bakeCubeMap(map, settings.box, settings.kind, settings.size);
    }
    cube.inputHash = bakeInputHash(settings);
    if (report) {
        report->mapSeconds = mapSeconds;
        report->bakeSeconds = secondsSince(start) - mapSeconds;
    }
    return cube;
}

std::filesystem::path cubeMapCacheDirectory() {
    if (const char* dir = std::getenv("CVC_CACHE_DIR"); dir && *dir) return dir;
    if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) {
        return std::filesystem::path(xdg) / "conformal-vc";
    }
    if (const char* home = std::getenv("HOME"); home && *home) {
        return std::filesystem::path(home) / ".cache" / "conformal-vc";
    }
    return std::filesystem::temp_directory_path() / "conformal-vc";
}

CubeMap cachedCubeMap(const BakeSettings& settings, BakeReport* report) {
    requireBakeableKind(settings.kind);
    const std::uint64_t hash = bakeInputHash(settings);
    std::ostringstream name;
    name << "cubemap-" << std::hex << std::setw(16) << std::setfill('0') << hash << ".cvcm";
    const std::filesystem::path path = cubeMapCacheDirectory() / name.str();
    BakeReport localReport;
    BakeReport& out = report ? *report : localReport;
    out.cachePath = path;
    std::error_code error;
    if (std::filesystem::exists(path, error)) {
        try {
            const auto start = std::chrono::steady_clock::now();
            CubeMap cube = loadCubeMap(path);
            if (cube.inputHash == hash && cube.size == settings.size) {
                out.wasLoadedFromCache = true;
                out.bakeSeconds = secondsSince(start);
                return cube;
            }
        } catch (const CubeMapFileError&) {
            // A damaged cache entry is rebuilt below and overwritten.
        }
    }
    CubeMap cube = bakeCubeMap(settings, &out);
    std::filesystem::create_directories(path.parent_path(), error);
    try {
        saveCubeMap(cube, path);
    } catch (const std::exception&) {
        // The cache is an optimisation: a read-only cache directory must not fail the bake.
    }
    return cube;
}

}  // namespace conformal
