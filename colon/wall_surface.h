/// @brief The colon wall as a surface: the iso-surface the renderer shows (the air / wall
/// boundary at the render's iso value), meshed by OpenVDB's volumeToMesh and kept only where
/// it bounds the colon lumen, so coverage is measured over the colon and not over the skin, the
/// lungs or the small bowel. Each polygon is one surface element, with its area, centre and
/// the normal pointing into the lumen (toward the air, the side a viewer inside looks from).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "volumes/volume.h"

namespace colon {

struct WallSurface {
    std::vector<glm::dvec3> vertices;              ///< volume millimetres
    std::vector<std::array<uint32_t, 4>> quads;    ///< vertex indices, counter-clockwise seen from the lumen
    std::vector<double> areaMm2;                   ///< per quad
    std::vector<glm::dvec3> centreMm;              ///< per quad: the mean of its corners
    std::vector<glm::dvec3> normal;                ///< per quad: unit, pointing into the lumen
    double totalAreaMm2 = 0.0;

    [[nodiscard]] std::size_t size() const { return quads.size(); }
};

struct WallSurfaceSettings {
    double isoHu = -500.0;
    /// A polygon belongs to the colon wall when its centre lies within this many millimetres of
    /// a lumen voxel's centre: the iso-surface lies between the last air voxel and the first
    /// wall voxel, so one voxel diagonal (plus a margin) reaches it from the lumen side.
    double maxDistanceFromLumenVoxels = 1.5;
};

/// Meshes the iso-surface of `volume` around the voxels where `isLumen` is non-zero (one
/// byte per voxel of `volume`) and keeps the polygons that bound the lumen. Throws ColonError
/// for a mask of the wrong size or an empty result (no lumen, or an iso value the lumen's
/// boundary never crosses).
WallSurface colonWallSurface(const volumes::Volume& volume, const std::vector<uint8_t>& isLumen,
                             const WallSurfaceSettings& settings = {});

}  // namespace colon
