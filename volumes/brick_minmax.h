/// @brief Per-brick HU ranges over 8^3 bricks (the OpenVDB leaf size) for empty-space
/// skipping: which bricks can contribute to an iso-surface or a transfer function.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "volumes/volume.h"

namespace volumes {

/// Voxels along one edge of a brick (an OpenVDB leaf node is 8^3).
inline constexpr int kBrickSize = 8;

/// The HU range of every 8^3 brick of a volume, widened by the one-voxel apron that trilinear
/// filtering reads: brick (bx, by, bz) covers voxels [8b - 1, 8b + 8] per axis, clamped to the
/// volume. Brick (bx, by, bz) is stored at index bx + brickDims[0] * (by + brickDims[1] * bz),
/// so minHu/maxHu upload as a 3D image of brickDims = ceil(dims / 8) texels.
struct BrickMinMax {
    int brickSize = kBrickSize;  ///< voxels along a brick's edge (8, or finer for the renderer's skipping)
    std::array<int, 3> brickDims{0, 0, 0};
    std::vector<int16_t> minHu;
    std::vector<int16_t> maxHu;

    [[nodiscard]] std::size_t brickCount() const {
        return static_cast<std::size_t>(brickDims[0]) * static_cast<std::size_t>(brickDims[1]) *
               static_cast<std::size_t>(brickDims[2]);
    }
    [[nodiscard]] std::size_t brickIndex(int bx, int by, int bz) const {
        return static_cast<std::size_t>(bx) +
               static_cast<std::size_t>(brickDims[0]) *
                   (static_cast<std::size_t>(by) +
                    static_cast<std::size_t>(brickDims[1]) * static_cast<std::size_t>(bz));
    }
};

/// Brick counts per axis for a volume of `dims` voxels: ceil(dims / brickSize).
std::array<int, 3> brickDimsFor(const std::array<int, 3>& dims, int brickSize = kBrickSize);

/// Builds the ranges from the dense voxels with separable min/max passes (x, then y, then z),
/// about 1.3 reads per voxel. `brickSize` (1..64) other than 8 gives finer or coarser cells
/// with the same one-voxel apron: [s b - 1, s b + s] per axis.
BrickMinMax buildBrickMinMax(const Volume& volume, int brickSize = kBrickSize);

/// Marks the bricks an iso-surface at `isoHu` can pass through: those whose range (apron
/// included) satisfies min <= iso <= max. One byte per brick, 1 = may contribute.
std::vector<uint8_t> bricksForIsoValue(const BrickMinMax& bricks, double isoHu);

/// A 1D opacity table over HU: entry e covers HU in [firstHu + e * binHu, firstHu + (e+1) * binHu);
/// HU below firstHu use entry 0 and HU past the end use the last entry (clamp-to-edge, as a
/// GPU sampler would).
struct OpacityTable {
    double firstHu = -1024.0;
    double binHu = 1.0;
    std::vector<float> opacity;
};

/// Marks the bricks where any HU in [min, max] may have non-zero opacity in `table`, so a
/// brick is skipped only if every sample inside it is fully transparent. The bins holding min
/// and max and one more bin on each side are checked, which stays correct when the renderer
/// interpolates linearly between neighbouring entries.
std::vector<uint8_t> bricksForOpacity(const BrickMinMax& bricks, const OpacityTable& table);

/// Marks the bricks for which `isVisibleInRange(minHu, maxHu)` is true: a predicate that says
/// whether any HU in the closed range has non-zero opacity.
std::vector<uint8_t> bricksForPredicate(const BrickMinMax& bricks,
                                        const std::function<bool(int16_t minHu, int16_t maxHu)>& isVisibleInRange);

}  // namespace volumes
