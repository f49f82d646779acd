#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "conformal/linear_map.h"

namespace conformal {
namespace {

TEST(LinearMap, CeilingEdgeGoesToTheZenithAndInverseHolds) {
    for (const CaveBox& box : {CaveBox{}, immersiveCabinBox()}) {
        const LinearMap map(box);
        for (const auto& corner : ceilingCornerDirections(box)) {
            EXPECT_NEAR(map.sceneFromDisplay(corner).y, 1.0, 1e-12);
        }
        EXPECT_NEAR(map.sceneFromDisplay({0.0, -1.0, 0.0}).y, -1.0, 1e-15);
        for (double a = 0.05; a < 6.28; a += 0.3) {
            for (double polar = 0.1; polar < 1.9; polar += 0.3) {
                const glm::dvec3 d(std::sin(polar) * std::cos(a), -std::cos(polar), std::sin(polar) * std::sin(a));
                EXPECT_LT(glm::length(map.displayFromScene(map.sceneFromDisplay(d)) - d), 1e-12);
            }
        }
    }
}

}  // namespace
}  // namespace conformal
