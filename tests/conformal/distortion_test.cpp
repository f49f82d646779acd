#include <cmath>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "conformal/cube_map_baker.h"
#include "conformal/distortion.h"
#include "conformal/linear_map.h"
#include "test_maps.h"

namespace conformal {
namespace {

TEST(Distortion, JacobianOfAKnownStretch) {
    // The map (x, y) -> (2x, y) near the nadir of a flat chart: K = 2, scale sqrt(2).
    const glm::dvec3 d(0.0, 0.0, 1.0);
    const MapJacobian j = jacobianFromDifferences(d, {1e-3, 0, 0}, {0, 1e-3, 0}, d, {2e-3, 0, 0}, {0, 1e-3, 0});
    EXPECT_NEAR(j.quasiConformal, 2.0, 1e-12);
    EXPECT_NEAR(j.scale, std::sqrt(2.0), 1e-12);
    EXPECT_EQ(j.orientation, 1.0);
    const MapJacobian mirrored = jacobianFromDifferences(d, {1e-3, 0, 0}, {0, 1e-3, 0}, d, {-1e-3, 0, 0}, {0, 1e-3, 0});
    EXPECT_EQ(mirrored.orientation, -1.0);
}

TEST(Distortion, ConformalMapIsNearlyConformalAndNeverFolds) {
    for (const ConformalMap* map : {&testing::cubeMap(), &testing::cabinMap()}) {
        const CubeMap cube = bakeCubeMap(*map, map->settings().box, MapKind::Conformal, 128);
        const DistortionStatistics stats = distortionStatistics(cube, 1.0);
        EXPECT_GT(stats.texelCount, 60000);
        EXPECT_EQ(stats.foldedTexels, 0);
        // No fold-over anywhere in Omega5, corners included.
        EXPECT_EQ(distortionStatistics(cube, 0.0).foldedTexels, 0);
        // At this coarse test resolution the singular points on the ceiling's edges dominate.
        EXPECT_LT(stats.meanK - 1.0, 2e-2);
        EXPECT_LT(stats.p99K - 1.0, 0.25);
        // Away from the corners and the ceiling's edges the map is conformal to mesh accuracy.
        const DistortionStatistics walls = distortionStatistics(cube, 15.0);
        EXPECT_LT(walls.meanK - 1.0, 2e-3);
    }
}

TEST(Distortion, LinearBaselineIsNotConformal) {
    const CubeMap cube = bakeCubeMap(LinearMap(CaveBox{}), CaveBox{}, MapKind::Linear, 128);
    const DistortionStatistics stats = distortionStatistics(cube, 1.0);
    EXPECT_EQ(stats.foldedTexels, 0);
    EXPECT_GT(stats.meanK - 1.0, 0.1);
}

TEST(Distortion, ScaleChannelIsTheLocalScale) {
    // A: sqrt(det dF). The linear baseline stretches polar angles by pi / thetaEdge along
    // longitudes and keeps azimuths: near the nadir both directions scale by that factor.
    const LinearMap map(CaveBox{});
    const CubeMap cube = bakeCubeMap(map, CaveBox{}, MapKind::Linear, 128);
    // At azimuth 0 (a wall's middle) the edge angle is stationary, so dF is diagonal there:
    // k = pi / thetaEdge along the longitude and sin(k theta) / sin(theta) along the parallel.
    const double k = 3.14159265358979 / map.edgeAngleFromNadir(0.0);
    const double polar = 0.5;
    const double expected = std::sqrt(k * std::sin(k * polar) / std::sin(polar));
    const glm::vec4 texel = sampleCubeMapBilinear(cube, {std::sin(polar), -std::cos(polar), 0.0});
    EXPECT_NEAR(texel.w, expected, 2e-3);
}

}  // namespace
}  // namespace conformal
