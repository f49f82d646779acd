#include "volumes/brick_minmax.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "volumes/parallel_for.h"

namespace volumes {
namespace {

/// Min/max over the apron-widened brick windows along one axis of a 3D array.
///
/// `in` has extents (n0, n1, n2) with the reduced axis `axis`; the output has the same
/// extents except ceil(n_axis / 8) along `axis`. Window b covers [8b - 1, 8b + 8] clamped.
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

    // Strides of the reduced axis in input and output; lines run along it.
    const std::size_t inStride = axis == 0   ? 1
                                 : axis == 1 ? static_cast<std::size_t>(extents[0])
                                             : static_cast<std::size_t>(extents[0]) * extents[1];
    const std::size_t outStride = axis == 0   ? 1
                                  : axis == 1 ? static_cast<std::size_t>(outExtents[0])
                                              : static_cast<std::size_t>(outExtents[0]) * outExtents[1];
    const std::array<int, 3> lineExtents{axis == 0 ? 1 : extents[0], axis == 1 ? 1 : extents[1],
                                         axis == 2 ? 1 : extents[2]};
    // Planes of lines are independent: one per parallel item.
    parallelFor(lineExtents[2], [&](int c) {
        for (int b = 0; b < lineExtents[1]; ++b) {
            for (int a = 0; a < lineExtents[0]; ++a) {
                const std::size_t inBase = static_cast<std::size_t>(a) +
                                           static_cast<std::size_t>(extents[0]) *
                                               (static_cast<std::size_t>(b) + static_cast<std::size_t>(extents[1]) * c);
                const std::size_t outBase =
                    static_cast<std::size_t>(a) +
                    static_cast<std::size_t>(outExtents[0]) *
                        (static_cast<std::size_t>(b) + static_cast<std::size_t>(outExtents[1]) * c);
                for (int brick = 0; brick < bricks; ++brick) {
                    const int first = std::max(brick * brickSize - 1, 0);
                    const int last = std::min(brick * brickSize + brickSize, n - 1);
                    int16_t lo = std::numeric_limits<int16_t>::max(), hi = std::numeric_limits<int16_t>::min();
                    for (int v = first; v <= last; ++v) {
                        const std::size_t at = inBase + static_cast<std::size_t>(v) * inStride;
                        lo = std::min(lo, inMin[at]);
                        hi = std::max(hi, inMax[at]);
                    }
                    outMin[outBase + static_cast<std::size_t>(brick) * outStride] = lo;
                    outMax[outBase + static_cast<std::size_t>(brick) * outStride] = hi;
                }
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
