// The Chebyshev distance map against brute force on random occupancies.
#include <random>

#include <gtest/gtest.h>

#include "engine/render/empty_space_map.h"

namespace {

TEST(EmptySpaceMap, MatchesBruteForceChebyshevDistance) {
    std::mt19937 random(5);
    for (double density : {0.002, 0.02, 0.2}) {
        const std::array<int, 3> dims{23, 17, 11};
        std::vector<uint8_t> occupied(static_cast<std::size_t>(dims[0] * dims[1] * dims[2]));
        std::bernoulli_distribution isSet(density);
        for (auto& o : occupied) o = isSet(random) ? 1 : 0;
        const auto d = engine::chebyshevDistanceMap(occupied, dims);
        for (int z = 0; z < dims[2]; ++z) {
            for (int y = 0; y < dims[1]; ++y) {
                for (int x = 0; x < dims[0]; ++x) {
                    int best = engine::kMaxSkipDistance;
                    for (int k = 0; k < dims[2]; ++k) {
                        for (int j = 0; j < dims[1]; ++j) {
                            for (int i = 0; i < dims[0]; ++i) {
                                if (occupied[static_cast<std::size_t>(i + dims[0] * (j + dims[1] * k))]) {
                                    best = std::min(best, std::max({std::abs(i - x), std::abs(j - y), std::abs(k - z)}));
                                }
                            }
                        }
                    }
                    ASSERT_EQ(d[static_cast<std::size_t>(x + dims[0] * (y + dims[1] * z))], best)
                        << "cell " << x << "," << y << "," << z << " density " << density;
                }
            }
        }
    }
}

// Other shapes (lines, planes, one cell) and clustered occupancy, where the envelope's segments
// tie over long plateaus: every cell against the nearest occupied cell found by brute force.
TEST(EmptySpaceMap, MatchesBruteForceOnFlatGridsAndClusters) {
    std::mt19937 random(11);
    const std::array<std::array<int, 3>, 6> shapes{{{1, 1, 1}, {40, 1, 1}, {1, 1, 37}, {1, 29, 3}, {31, 2, 19}, {9, 9, 9}}};
    for (const auto& dims : shapes) {
        for (int clusters : {0, 1, 3}) {
            std::vector<uint8_t> occupied(static_cast<std::size_t>(dims[0] * dims[1] * dims[2]), 0);
            std::uniform_int_distribution<int> cx(0, dims[0] - 1), cy(0, dims[1] - 1), cz(0, dims[2] - 1);
            for (int c = 0; c < clusters; ++c) {
                // A box of up to 3 cells a side around a random cell.
                const int x0 = cx(random), y0 = cy(random), z0 = cz(random);
                for (int z = z0; z < std::min(z0 + 3, dims[2]); ++z) {
                    for (int y = y0; y < std::min(y0 + 2, dims[1]); ++y) {
                        for (int x = x0; x < std::min(x0 + 3, dims[0]); ++x) {
                            occupied[static_cast<std::size_t>(x + dims[0] * (y + dims[1] * z))] = 1;
                        }
                    }
                }
            }
            const auto d = engine::chebyshevDistanceMap(occupied, dims);
            for (int z = 0; z < dims[2]; ++z) {
                for (int y = 0; y < dims[1]; ++y) {
                    for (int x = 0; x < dims[0]; ++x) {
                        int best = engine::kMaxSkipDistance;
                        for (std::size_t i = 0; i < occupied.size(); ++i) {
                            if (!occupied[i]) continue;
                            const int ox = static_cast<int>(i) % dims[0], oy = static_cast<int>(i) / dims[0] % dims[1],
                                      oz = static_cast<int>(i) / (dims[0] * dims[1]);
                            best = std::min(best, std::max({std::abs(ox - x), std::abs(oy - y), std::abs(oz - z)}));
                        }
                        ASSERT_EQ(d[static_cast<std::size_t>(x + dims[0] * (y + dims[1] * z))], best)
                            << "cell " << x << "," << y << "," << z << " of " << dims[0] << "x" << dims[1] << "x"
                            << dims[2] << ", " << clusters << " clusters";
                    }
                }
            }
        }
    }
}

// Past kMaxSkipDistance cells the map holds the cap, along every axis.
TEST(EmptySpaceMap, DistancesBeyondTheCapReadTheCap) {
    for (int axis = 0; axis < 3; ++axis) {
        std::array<int, 3> dims{2, 2, 2};
        dims[static_cast<std::size_t>(axis)] = 300;
        std::vector<uint8_t> occupied(static_cast<std::size_t>(dims[0] * dims[1] * dims[2]), 0);
        occupied[0] = 1;  // the cell (0, 0, 0)
        const auto d = engine::chebyshevDistanceMap(occupied, dims);
        const std::size_t stride = axis == 0 ? 1 : axis == 1 ? 2 : 4;
        for (int k = 0; k < 300; ++k) {
            EXPECT_EQ(d[static_cast<std::size_t>(k) * stride], std::min(k, engine::kMaxSkipDistance))
                << "axis " << axis << ", cell " << k;
        }
    }
}

TEST(EmptySpaceMap, EmptyGridIsFarEverywhereAndSizesAreChecked) {
    const auto d = engine::chebyshevDistanceMap(std::vector<uint8_t>(64, 0), {4, 4, 4});
    for (uint8_t v : d) EXPECT_EQ(v, engine::kMaxSkipDistance);
    EXPECT_THROW(engine::chebyshevDistanceMap(std::vector<uint8_t>(63, 0), {4, 4, 4}), std::invalid_argument);
}

}  // namespace
