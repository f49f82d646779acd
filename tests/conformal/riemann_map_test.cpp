#include <cmath>

#include <gtest/gtest.h>

#include "conformal/conformal_map.h"
#include "conformal/scene_disk_closed_form.h"
#include "test_maps.h"

namespace conformal {
namespace {

using Complex = std::complex<double>;

/// Mean |phi6 - closed form| over the scene mesh's vertices off the slit.
double meanSceneDiskError(const ConformalMap& map) {
    const SphereMesh& mesh = map.sceneMesh();
    double sum = 0.0;
    int count = 0;
    for (std::size_t v = 0; v < mesh.mesh.positions.size(); ++v) {
        if (mesh.slitSector[v] >= 0) continue;
        const Complex exact = sceneDiskFromDirectionClosedForm(map.settings().box, mesh.mesh.positions[v]);
        sum += std::abs(map.sceneDisk()[v] - exact);
        ++count;
    }
    return sum / count;
}

TEST(RiemannMap, SceneDiskConvergesToClosedFormAtSecondOrder) {
    std::vector<double> errors;
    for (const int resolution : {12, 24, 48}) {
        ConformalMapSettings settings;
        settings.mesh.resolution = resolution;
        settings.isExtrapolated = false;
        const ConformalMap map(settings);
        errors.push_back(meanSceneDiskError(map));
    }
    for (std::size_t k = 1; k < errors.size(); ++k) {
        const double order = std::log2(errors[k - 1] / errors[k]);
        EXPECT_GT(order, 1.7) << "between levels " << k - 1 << " and " << k << ": " << errors[k - 1]
                              << " -> " << errors[k];
    }
    // Richardson extrapolation from the half-resolution mesh must beat the plain flow by far.
    EXPECT_LT(meanSceneDiskError(testing::cubeMap()), 0.25 * errors.back());
}

TEST(RiemannMap, CornersAndNadirLandWhereSymmetryPutsThem) {
    for (const ConformalMap* map : {&testing::cubeMap(), &testing::cabinMap()}) {
        const std::array<Complex, 4> expected = {Complex(1, 0), Complex(0, 1), Complex(-1, 0), Complex(0, -1)};
        for (int k = 0; k < 4; ++k) {
            EXPECT_NEAR(std::abs(map->sceneDisk()[map->sceneMesh().cornerVertices[k]] - expected[k]), 0.0, 1e-9);
            EXPECT_NEAR(std::abs(map->displayDisk()[map->displayMesh().cornerVertices[k]] - expected[k]), 0.0, 1e-9);
        }
        EXPECT_LT(std::abs(map->report().sceneNadir), 1e-9);
        EXPECT_LT(std::abs(map->report().displayNadir), 1e-9);
        EXPECT_LT(map->report().scene.flow.maxCurvatureError, 1e-10);
        EXPECT_LT(map->report().display.flow.maxCurvatureError, 1e-10);
        EXPECT_LT(map->report().scene.outerRadiusError, 1e-9);
        EXPECT_LT(map->report().display.outerRadiusError, 1e-9);
    }
}

TEST(RiemannMap, ClosedFormIsItsOwnInverse) {
    const CaveBox box;
    for (double r = 0.05; r < 1.0; r += 0.1) {
        for (double a = 0.1; a < 6.28; a += 0.37) {
            const Complex zeta = std::polar(r, a);
            const Complex back = sceneDiskFromDirectionClosedForm(box, directionFromSceneDiskClosedForm(box, zeta));
            EXPECT_NEAR(std::abs(back - zeta), 0.0, 1e-12);
        }
    }
}

}  // namespace
}  // namespace conformal
