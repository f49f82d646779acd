#include "volumes/brick_minmax.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "volumes/parallel_for.h"

namespace volumes {
namespace {

/// The voxels along one axis whose values brick `brick` depends on: its own and the one-voxel
/// apron on each side that trilinear filtering reads, clamped to the axis's n voxels.
struct BrickWindow {
    int first;
    int last;
};

BrickWindow brickWindowOf(int brick, int brickSize, int n) {
    return {std::max(brick * brickSize - 1, 0), std::min(brick * brickSize + brickSize, n - 1)};
}

/// Min/max over the apron-widened brick windows along one axis of a 3D array.
///
/// `in` has extents (n0, n1, n2) with the reduced axis `axis`; the output has the same
/// extents except ceil(n_axis / s) along `axis` (s = brickSize). Window b covers
/// [s b - 1, s b + s] clamped: the brick and the one-voxel apron trilinear filtering reads.
void reduceAxis(const std::vector<int16_t>& inMin, const std::vector<int16_t>& inMax, std::array<int, 3> extents,
                int axis, int brickSize, std::vector<int16_t>& outMin, std::vector<int16_t>& outMax) {
    const int n = extents[static_cast<std::size_t>(axis)];
    const int bricks = (n + brickSize - 1) / brickSize;
    std::array<int, 3> outExtents = extents;
    outExtents[static_cast<std::size_t>(axis)] = bricks;
    const std::size_t outCount = static_cast<std::size_t>(outExtents[0]) * static_cast<std::size_t>(outExtents[1]) *
                                 static_cast<std::size_t>(outExtents[2]);
    outMin.assign(outCount, 0);
    outMax.assign(outCount, 0);

    if (axis != 0) {
        // Along y or z the data are rows of `inner` contiguous values, n rows per block of
        // `outer`: each output row is the min/max of its window's input rows, read and written
        // contiguously (a strided walk along the axis was most of a 1-voxel-cell build).
        const std::size_t inner = axis == 1 ? static_cast<std::size_t>(extents[0])
                                            : static_cast<std::size_t>(extents[0]) * extents[1];
        const int outer = axis == 1 ? extents[2] : 1;
        parallelFor(outer * bricks, [&](int item) {
            const auto block = static_cast<std::size_t>(item / bricks);
            const int brick = item % bricks;
            const BrickWindow window = brickWindowOf(brick, brickSize, n);
            int16_t* lo = outMin.data() + (block * bricks + static_cast<std::size_t>(brick)) * inner;
            int16_t* hi = outMax.data() + (block * bricks + static_cast<std::size_t>(brick)) * inner;
            std::fill_n(lo, inner, std::numeric_limits<int16_t>::max());
            std::fill_n(hi, inner, std::numeric_limits<int16_t>::min());
            for (int v = window.first; v <= window.last; ++v) {
                const std::size_t row = (block * static_cast<std::size_t>(n) + static_cast<std::size_t>(v)) * inner;
                const int16_t* rowMin = inMin.data() + row;
                const int16_t* rowMax = inMax.data() + row;
                for (std::size_t i = 0; i < inner; ++i) {
                    lo[i] = std::min(lo[i], rowMin[i]);
                    hi[i] = std::max(hi[i], rowMax[i]);
                }
            }
        });
        return;
    }

    // Along x, lines are contiguous: one z plane of lines per parallel item.
    parallelFor(extents[2], [&](int z) {
        for (int y = 0; y < extents[1]; ++y) {
            const std::size_t line = static_cast<std::size_t>(y) + static_cast<std::size_t>(extents[1]) * z;
            const int16_t* lineMin = inMin.data() + line * static_cast<std::size_t>(n);
            const int16_t* lineMax = inMax.data() + line * static_cast<std::size_t>(n);
            for (int brick = 0; brick < bricks; ++brick) {
                const BrickWindow window = brickWindowOf(brick, brickSize, n);
                int16_t lo = std::numeric_limits<int16_t>::max(), hi = std::numeric_limits<int16_t>::min();
                for (int v = window.first; v <= window.last; ++v) {
                    lo = std::min(lo, lineMin[v]);
                    hi = std::max(hi, lineMax[v]);
                }
                outMin[line * static_cast<std::size_t>(bricks) + static_cast<std::size_t>(brick)] = lo;
                outMax[line * static_cast<std::size_t>(bricks) + static_cast<std::size_t>(brick)] = hi;
            }
        }
    });
}

}  // namespace

std::array<int, 3> brickDimsFor(const std::array<int, 3>& dims, int brickSize) {
    return {(dims[0] + brickSize - 1) / brickSize, (dims[1] + brickSize - 1) / brickSize,
            (dims[2] + brickSize - 1) / brickSize};
}

BrickMinMax buildBrickMinMax(const Volume& volume, int brickSize) {
    validateVolume(volume, "brick min/max input");
    if (brickSize < 1 || brickSize > 64) throw VolumeError("brick size " + std::to_string(brickSize) + " is outside 1..64");
    BrickMinMax bricks;
    bricks.brickSize = brickSize;
    bricks.brickDims = brickDimsFor(volume.dims, brickSize);

    // Pass x reads the voxels once (as both min and max input); passes y and z read the
    // already reduced arrays (1/8 and 1/64 of the volume for 8^3 bricks).
    std::vector<int16_t> xMin, xMax, yMin, yMax;
    reduceAxis(volume.hu, volume.hu, volume.dims, 0, brickSize, xMin, xMax);
    std::array<int, 3> extents{bricks.brickDims[0], volume.dims[1], volume.dims[2]};
    reduceAxis(xMin, xMax, extents, 1, brickSize, yMin, yMax);
    xMin = {};
    xMax = {};
    extents[1] = bricks.brickDims[1];
    reduceAxis(yMin, yMax, extents, 2, brickSize, bricks.minHu, bricks.maxHu);
    return bricks;
}

std::vector<uint8_t> bricksForIsoValue(const BrickMinMax& bricks, double isoHu) {
    std::vector<uint8_t> mask(bricks.brickCount(), 0);
    for (std::size_t b = 0; b < mask.size(); ++b) {
        mask[b] = bricks.minHu[b] <= isoHu && isoHu <= bricks.maxHu[b] ? 1 : 0;
    }
    return mask;
}

std::vector<uint8_t> bricksForOpacity(const BrickMinMax& bricks, const OpacityTable& table) {
    std::vector<uint8_t> mask(bricks.brickCount(), 0);
    const long long binCount = static_cast<long long>(table.opacity.size());
    if (binCount == 0 || !(table.binHu > 0.0) || !std::isfinite(table.firstHu)) {
        throw VolumeError("opacity table: needs at least one bin, a positive bin width and a finite start");
    }
    // visibleBefore[e] = number of bins < e with non-zero opacity.
    std::vector<long long> visibleBefore(static_cast<std::size_t>(binCount) + 1, 0);
    for (long long e = 0; e < binCount; ++e) {
        visibleBefore[static_cast<std::size_t>(e) + 1] =
            visibleBefore[static_cast<std::size_t>(e)] + (table.opacity[static_cast<std::size_t>(e)] > 0.0f ? 1 : 0);
    }
    auto binOf = [&](double hu) {
        const double e = std::floor((hu - table.firstHu) / table.binHu);
        return static_cast<long long>(std::clamp(e, 0.0, static_cast<double>(binCount - 1)));
    };
    for (std::size_t b = 0; b < mask.size(); ++b) {
        const long long first = std::max(binOf(bricks.minHu[b]) - 1, 0LL);
        const long long last = std::min(binOf(bricks.maxHu[b]) + 1, binCount - 1);
        mask[b] =
            visibleBefore[static_cast<std::size_t>(last) + 1] > visibleBefore[static_cast<std::size_t>(first)] ? 1 : 0;
    }
    return mask;
}

std::vector<uint8_t> bricksForPredicate(const BrickMinMax& bricks,
                                        const std::function<bool(int16_t minHu, int16_t maxHu)>& isVisibleInRange) {
    std::vector<uint8_t> mask(bricks.brickCount(), 0);
    for (std::size_t b = 0; b < mask.size(); ++b) {
        mask[b] = isVisibleInRange(bricks.minHu[b], bricks.maxHu[b]) ? 1 : 0;
    }
    return mask;
}

}  // namespace volumes
