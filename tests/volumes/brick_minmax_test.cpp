/// Brick min/max against brute force on random volumes, and the property skipping relies on:
/// a brick marked empty holds no voxel (apron included) that could contribute.
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "tests/volumes/test_support.h"
#include "volumes/brick_minmax.h"
#include "volumes/vdb_io.h"

namespace volumes {
namespace {

/// A random volume: smooth-ish blobs over air with salt noise, so bricks differ a lot.
Volume randomVolume(std::array<int, 3> dims, unsigned seed) {
    std::mt19937 rng(seed);
    Volume v;
    v.dims = dims;
    v.hu.assign(v.voxelCount(), -1000);
    std::uniform_int_distribution<int> hu(-1024, 3000), coin(0, 99);
    for (int k = 0; k < dims[2]; ++k)
        for (int j = 0; j < dims[1]; ++j)
            for (int i = 0; i < dims[0]; ++i) {
                const bool isBlob = ((i / 5 + j / 7 + k / 3) % 4) == 0;
                if (isBlob || coin(rng) < 3) v.hu[v.linearIndex(i, j, k)] = static_cast<int16_t>(hu(rng));
            }
    return v;
}

/// The range over voxels [8b - 1, 8b + 8] (clamped), counted the slow way.
std::pair<int16_t, int16_t> bruteForceRange(const Volume& v, int bx, int by, int bz) {
    int16_t lo = std::numeric_limits<int16_t>::max(), hi = std::numeric_limits<int16_t>::min();
    for (int k = std::max(8 * bz - 1, 0); k <= std::min(8 * bz + 8, v.dims[2] - 1); ++k)
        for (int j = std::max(8 * by - 1, 0); j <= std::min(8 * by + 8, v.dims[1] - 1); ++j)
            for (int i = std::max(8 * bx - 1, 0); i <= std::min(8 * bx + 8, v.dims[0] - 1); ++i) {
                lo = std::min(lo, v.at(i, j, k));
                hi = std::max(hi, v.at(i, j, k));
            }
    return {lo, hi};
}

/// Trilinear sample at continuous voxel coordinates p (voxel centres at integers), clamped.
double trilinear(const Volume& v, glm::dvec3 p) {
    for (int a = 0; a < 3; ++a)
        p[a] = std::clamp(p[a], 0.0, static_cast<double>(v.dims[static_cast<std::size_t>(a)] - 1));
    const glm::ivec3 base(static_cast<int>(std::floor(p.x)), static_cast<int>(std::floor(p.y)),
                          static_cast<int>(std::floor(p.z)));
    const glm::dvec3 t = p - glm::dvec3(base);
    double sum = 0.0;
    for (int c = 0; c < 8; ++c) {
        const int i = std::min(base.x + (c & 1), v.dims[0] - 1);
        const int j = std::min(base.y + ((c >> 1) & 1), v.dims[1] - 1);
        const int k = std::min(base.z + ((c >> 2) & 1), v.dims[2] - 1);
        const double w =
            ((c & 1) ? t.x : 1 - t.x) * (((c >> 1) & 1) ? t.y : 1 - t.y) * (((c >> 2) & 1) ? t.z : 1 - t.z);
        sum += w * v.at(i, j, k);
    }
    return sum;
}

const std::array<int, 3> kShapes[] = {{8, 8, 8}, {1, 1, 1}, {17, 9, 30}, {64, 33, 7}, {5, 40, 16}, {9, 12, 150}};

TEST(BrickMinMax, MatchesBruteForce) {
    unsigned seed = 1;
    for (const auto& dims : kShapes) {
        const Volume v = randomVolume(dims, seed++);
        const BrickMinMax bricks = buildBrickMinMax(v);
        ASSERT_EQ(bricks.brickDims, brickDimsFor(dims));
        ASSERT_EQ(bricks.minHu.size(), bricks.brickCount());
        for (int bz = 0; bz < bricks.brickDims[2]; ++bz)
            for (int by = 0; by < bricks.brickDims[1]; ++by)
                for (int bx = 0; bx < bricks.brickDims[0]; ++bx) {
                    const auto [lo, hi] = bruteForceRange(v, bx, by, bz);
                    ASSERT_EQ(bricks.minHu[bricks.brickIndex(bx, by, bz)], lo) << bx << ',' << by << ',' << bz;
                    ASSERT_EQ(bricks.maxHu[bricks.brickIndex(bx, by, bz)], hi) << bx << ',' << by << ',' << bz;
                }
    }
}

TEST(BrickMinMax, SkippedBricksHoldNoIsoCrossing) {
    // Every trilinear sample taken anywhere in a brick (half a voxel beyond it included) lies
    // within the brick's range, so a brick whose range misses the iso value cannot hold a hit.
    const Volume v = randomVolume({40, 27, 19}, 42);
    const BrickMinMax bricks = buildBrickMinMax(v);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (int bz = 0; bz < bricks.brickDims[2]; ++bz)
        for (int by = 0; by < bricks.brickDims[1]; ++by)
            for (int bx = 0; bx < bricks.brickDims[0]; ++bx) {
                const std::size_t b = bricks.brickIndex(bx, by, bz);
                for (int s = 0; s < 200; ++s) {
                    const glm::dvec3 p =
                        glm::dvec3(bx, by, bz) * 8.0 - 0.5 + 9.0 * glm::dvec3(unit(rng), unit(rng), unit(rng));
                    const double value = trilinear(v, p);
                    ASSERT_GE(value, bricks.minHu[b] - 1e-9);
                    ASSERT_LE(value, bricks.maxHu[b] + 1e-9);
                }
            }
    for (const double iso : {-500.0, 0.0, 300.0, 2999.5}) {
        const auto mask = bricksForIsoValue(bricks, iso);
        for (std::size_t b = 0; b < mask.size(); ++b) {
            EXPECT_EQ(mask[b] != 0, bricks.minHu[b] <= iso && iso <= bricks.maxHu[b]);
        }
    }
}

TEST(BrickMinMax, SkippedBricksAreTransparentUnderAnOpacityTable) {
    Volume v = randomVolume({33, 25, 20}, 3);
    // The lower half in z holds no bone, so some bricks must be skipped.
    for (std::size_t n = 0; n < v.hu.size() / 2; ++n) v.hu[n] = static_cast<int16_t>(std::min<int>(v.hu[n], 200));
    const BrickMinMax bricks = buildBrickMinMax(v);
    // Opaque only for bone: 8 HU bins from -1024.
    OpacityTable table;
    table.firstHu = -1024;
    table.binHu = 8;
    table.opacity.assign(600, 0.0f);
    for (std::size_t e = 300; e < 400; ++e) table.opacity[e] = 0.5f;  // HU 1376 .. 2176
    const auto mask = bricksForOpacity(bricks, table);
    std::size_t skipped = 0;
    for (int bz = 0; bz < bricks.brickDims[2]; ++bz)
        for (int by = 0; by < bricks.brickDims[1]; ++by)
            for (int bx = 0; bx < bricks.brickDims[0]; ++bx) {
                if (mask[bricks.brickIndex(bx, by, bz)]) continue;
                ++skipped;
                for (int k = std::max(8 * bz - 1, 0); k <= std::min(8 * bz + 8, v.dims[2] - 1); ++k)
                    for (int j = std::max(8 * by - 1, 0); j <= std::min(8 * by + 8, v.dims[1] - 1); ++j)
                        for (int i = std::max(8 * bx - 1, 0); i <= std::min(8 * bx + 8, v.dims[0] - 1); ++i) {
                            const int hu = v.at(i, j, k);
                            ASSERT_FALSE(hu >= 1376 - 8 && hu < 2176 + 8) << "skipped brick holds visible HU " << hu;
                        }
            }
    EXPECT_GT(skipped, 0u);
    // The predicate form agrees with a range test written out.
    const auto byPredicate = bricksForPredicate(bricks, [](int16_t lo, int16_t hi) { return hi >= 1368 && lo < 2184; });
    EXPECT_EQ(byPredicate, mask);
}

TEST(BrickMinMax, FromVdbLeavesEqualsDenseOnRandomVolumes) {
    unsigned seed = 11;
    for (const auto& dims : kShapes) {
        const Volume v = randomVolume(dims, seed++);
        const std::string path = testing::scratchFolder("bricks_vdb") + "/v.vdb";
        writeVdb(v, path);
        BrickMinMax fromLeaves;
        const Volume back = readVdb(path, &fromLeaves);
        EXPECT_EQ(back.hu, v.hu);
        const BrickMinMax dense = buildBrickMinMax(v);
        EXPECT_EQ(fromLeaves.minHu, dense.minHu) << dims[0] << 'x' << dims[1] << 'x' << dims[2];
        EXPECT_EQ(fromLeaves.maxHu, dense.maxHu) << dims[0] << 'x' << dims[1] << 'x' << dims[2];
    }
}

}  // namespace
}  // namespace volumes
