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

TEST(EmptySpaceMap, EmptyGridIsFarEverywhereAndSizesAreChecked) {
    const auto d = engine::chebyshevDistanceMap(std::vector<uint8_t>(64, 0), {4, 4, 4});
    for (uint8_t v : d) EXPECT_EQ(v, engine::kMaxSkipDistance);
    EXPECT_THROW(engine::chebyshevDistanceMap(std::vector<uint8_t>(63, 0), {4, 4, 4}), std::invalid_argument);
}

}  // namespace
