/// @brief Bakes a direction map into a cube map, and caches bakes on disk by a hash of their
/// inputs.
#pragma once

#include <cstdint>
#include <filesystem>

#include "conformal/conformal_map.h"
#include "conformal/cube_map.h"

namespace conformal {

/// Everything a bake depends on.
struct BakeSettings {
    int size = 1024;  ///< texels per face edge
    CaveBox box;
    MapKind kind = MapKind::Conformal;
    SphereMeshSettings mesh;  ///< conformal map only
    RicciFlowSettings flow;   ///< conformal map only
};

/// Timings of a bake (seconds) and the conformal map's report when one was built.
struct BakeReport {
    double mapSeconds = 0.0;
    double bakeSeconds = 0.0;
    bool wasLoadedFromCache = false;
    std::filesystem::path cachePath;
};

/// Hash (FNV-1a, 64 bit) of the settings and of the baker's algorithm version.
std::uint64_t bakeInputHash(const BakeSettings& settings);

/// Samples `map` at every texel centre into RGB, and the local scale from differences of
/// neighbouring texels into A (see CubeMap). Uses all hardware threads. Throws
/// std::invalid_argument for MapKind::None (nothing to bake) and for a size outside [2, 8192].
CubeMap bakeCubeMap(const DirectionMap& map, const CaveBox& box, MapKind kind, int size);

/// Builds the map the settings ask for and bakes it. Throws std::invalid_argument on invalid
/// settings, MapKind::None among them.
CubeMap bakeCubeMap(const BakeSettings& settings, BakeReport* report = nullptr);

/// Where cached bakes live: $CVC_CACHE_DIR if set, else $XDG_CACHE_HOME/conformal-vc, else
/// $HOME/.cache/conformal-vc (created on demand).
std::filesystem::path cubeMapCacheDirectory();

/// Loads the bake for `settings` from the cache when a valid file with the same input hash is
/// there; otherwise bakes it and stores it (a cache that cannot be written is not an error).
/// Refuses MapKind::None like bakeCubeMap.
CubeMap cachedCubeMap(const BakeSettings& settings, BakeReport* report = nullptr);

}  // namespace conformal
