/// @brief The baked cube map of a direction map: Vulkan face order and texel rules, the file
/// format, and CPU bilinear sampling (the reference for the shader's samplerCube lookup).
#pragma once

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "conformal/cave_box.h"

namespace conformal {

/// Which map bends the view rays of a display, and which map a cube map holds. The values are
/// stored in cube-map files: keep them.
enum class MapKind : std::uint32_t {
    Conformal = 0,  ///< F = phi6^-1 o phi5 (the product's map)
    Linear = 1,     ///< the non-conformal baseline: polar angles scaled along longitudes
    None = 2,       ///< no bending: a display with every wall, or a render without the map.
                    ///< There is nothing to bake: baking refuses it and no cube-map file holds it.
};

/// "conformal", "linear" or "none".
std::string mapKindName(MapKind kind);
/// Parses "conformal", "linear" or "none"; throws std::invalid_argument listing them otherwise.
MapKind mapKindFromName(const std::string& name);

/// A cube map over display directions (seen from the box's map centre, CAVE space).
/// Texels: face f in Vulkan order (+X, -X, +Y, -Y, +Z, -Z), then row j (t), then texel i (s),
/// each RGBA float32: RGB = the unit scene direction F(d) in CAVE space, A = the map's local
/// linear scale sqrt(sigma_max sigma_min) = sqrt(det dF) (scene radians per display radian;
/// 1 where the map neither stretches nor compresses, < 1 where it compresses).
/// Texel (i, j) of a face sits at s = (i + 0.5) / size, t = (j + 0.5) / size.
struct CubeMap {
    int size = 0;
    CaveBox box;
    MapKind kind = MapKind::Conformal;
    std::uint64_t inputHash = 0;  ///< hash of the bake's inputs (see bakeInputHash)
    std::vector<float> rgba;      ///< 6 * size * size * 4 floats

    std::size_t texelIndex(int face, int i, int j) const {
        return ((static_cast<std::size_t>(face) * size + j) * size + i) * 4;
    }
};

/// Raised for unreadable, truncated or malformed cube-map files; the message names the file.
class CubeMapFileError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// The unit direction of face coordinates (s, t) in [0, 1] by Vulkan's cube-map rules
/// ("Cube Map Face Selection": +X sc = -z, tc = -y; -X sc = +z, tc = -y; +Y sc = +x, tc = +z;
/// -Y sc = +x, tc = -z; +Z sc = +x, tc = -y; -Z sc = -x, tc = -y; s = (sc / |ma| + 1) / 2).
/// s and t outside [0, 1] continue the face's plane.
glm::dvec3 directionFromCubeFace(int face, double s, double t);

/// Face selection by the major axis and the face's (s, t) of a non-zero direction.
struct CubeFaceCoordinate {
    int face = 0;
    double s = 0.0;
    double t = 0.0;
};
CubeFaceCoordinate cubeFaceFromDirection(const glm::dvec3& direction);

/// Bilinear lookup like a seamless samplerCube with linear filtering (taps beyond a face's edge
/// read the adjacent face's nearest texel).
glm::vec4 sampleCubeMapBilinear(const CubeMap& map, const glm::dvec3& direction);

/// File format (little-endian): the 8 bytes "CVCCUBE\0", uint32 version (2), uint32 size,
/// uint32 map kind, uint32 missing faces (bit f: face f in Vulkan order; version 1 files hold 0
/// here and are maps for a display without its ceiling), float64 box size[3], float64 map centre[3], uint64
/// input hash, uint64 payload byte count (= 6 size^2 16), then the texels as float32.
/// Throws CubeMapFileError for a map of kind None (such a file would be malformed).
void saveCubeMap(const CubeMap& map, const std::filesystem::path& path);
/// Reads and checks a file written by saveCubeMap; throws CubeMapFileError naming the file and
/// the problem (missing, wrong magic, unsupported version, bad size, a map kind other than
/// conformal or linear, truncated, trailing bytes, non-finite texels). The file size is checked
/// against the header before the texels are allocated.
CubeMap loadCubeMap(const std::filesystem::path& path);

}  // namespace conformal
