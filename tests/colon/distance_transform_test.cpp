// The exact Euclidean distance transform against brute force on random masks with
// anisotropic voxels, and connected components against the masks they came from.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "colon/connected_components.h"
#include "colon/distance_transform.h"

namespace {

TEST(DistanceTransform, EqualsBruteForceOnRandomAnisotropicMasks) {
    std::mt19937 random(7);
    for (const glm::dvec3 spacing : {glm::dvec3(1.0), glm::dvec3(0.7, 0.7, 3.0), glm::dvec3(2.0, 0.5, 1.3)}) {
        const colon::Grid grid{{13, 9, 11}, spacing};
        std::vector<uint8_t> inside(grid.voxelCount());
        std::bernoulli_distribution isInside(0.85);
        for (auto& v : inside) v = isInside(random) ? 1 : 0;
        const std::vector<float> distance = colon::distanceToOutsideMm(grid, inside);
        double worst = 0.0;
        for (int k = 0; k < grid.dims[2]; ++k)
            for (int j = 0; j < grid.dims[1]; ++j)
                for (int i = 0; i < grid.dims[0]; ++i) {
                    const std::size_t n = grid.index(i, j, k);
                    // Brute force over every outside voxel and the virtual ones beyond the faces.
                    double best = inside[n] ? 1e300 : 0.0;
                    if (inside[n]) {
                        best = std::min({(i + 1) * spacing.x, (grid.dims[0] - i) * spacing.x, (j + 1) * spacing.y,
                                         (grid.dims[1] - j) * spacing.y, (k + 1) * spacing.z, (grid.dims[2] - k) * spacing.z});
                        for (std::size_t m = 0; m < inside.size(); ++m) {
                            if (inside[m]) continue;
                            const auto v = grid.voxelOf(m);
                            best = std::min(best, glm::length(glm::dvec3(v[0] - i, v[1] - j, v[2] - k) * spacing));
                        }
                    }
                    worst = std::max(worst, std::abs(best - distance[n]));
                }
        EXPECT_LT(worst, 1e-4) << "spacing " << spacing.x << " " << spacing.y << " " << spacing.z;
    }
}

TEST(ConnectedComponents, SixConnectedRegionsAndTheirBoxes) {
    const colon::Grid grid{{6, 5, 4}, glm::dvec3(1.0)};
    std::vector<int32_t> labels(grid.voxelCount(), 0);
    // Two bars touching only along an edge: 6-connectivity keeps them apart.
    for (int i = 0; i < 6; ++i) labels[grid.index(i, 1, 1)] = colon::kUnlabelled;
    for (int i = 0; i < 6; ++i) labels[grid.index(i, 2, 2)] = colon::kUnlabelled;
    labels[grid.index(4, 4, 3)] = colon::kUnlabelled;
    labels[grid.index(0, 0, 0)] = -7;  // not in the mask: left alone
    const auto components = colon::labelComponents(grid, labels);
    ASSERT_EQ(components.size(), 3u);
    EXPECT_EQ(components[0].voxels, 6u);
    EXPECT_EQ(components[1].voxels, 6u);
    EXPECT_EQ(components[2].voxels, 1u);
    EXPECT_EQ(components[0].box.lo, (std::array<int, 3>{0, 1, 1}));
    EXPECT_EQ(components[0].box.hi, (std::array<int, 3>{5, 1, 1}));
    EXPECT_EQ(labels[grid.index(3, 2, 2)], components[1].label);
    EXPECT_EQ(labels[grid.index(0, 0, 0)], -7);
}

}  // namespace
