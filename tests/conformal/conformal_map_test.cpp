#include <algorithm>
#include <cmath>
#include <random>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include "conformal/conformal_map.h"
#include "test_maps.h"

namespace conformal {
namespace {

double angleBetween(const glm::dvec3& a, const glm::dvec3& b) {
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

std::vector<glm::dvec3> randomDirections(int count, unsigned seed) {
    std::mt19937 random(seed);
    std::normal_distribution<double> normal;
    std::vector<glm::dvec3> directions;
    for (int k = 0; k < count; ++k) {
        directions.push_back(glm::normalize(glm::dvec3(normal(random), normal(random), normal(random))));
    }
    return directions;
}

/// Largest angle between the direction and a ceiling corner's direction: keeps away from the
/// map's singular points in tests that compare with mesh-level accuracy.
double angleToNearestCorner(const CaveBox& box, const glm::dvec3& d) {
    double nearest = 10.0;
    for (const auto& corner : ceilingCornerDirections(box)) nearest = std::min(nearest, angleBetween(d, corner));
    return nearest;
}

double percentile(std::vector<double> values, double fraction) {
    const std::size_t k = std::min(values.size() - 1, static_cast<std::size_t>(fraction * static_cast<double>(values.size())));
    std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
    return values[k];
}

TEST(ConformalMap, InverseComposesToIdentity) {
    for (const ConformalMap* map : {&testing::cubeMap(), &testing::cabinMap()}) {
        const CaveBox& box = map->settings().box;
        std::vector<double> displayErrors;
        std::vector<double> sceneErrors;
        for (const glm::dvec3& d : randomDirections(4000, 3)) {
            if (angleToNearestCorner(box, d) < 0.05) continue;
            if (!isMissingDirection(box, d)) {
                displayErrors.push_back(angleBetween(map->displayFromScene(map->sceneFromDisplay(d)), d));
            }
            sceneErrors.push_back(angleBetween(map->sceneFromDisplay(map->displayFromScene(d)), d));
        }
        // Radians; the largest errors sit next to the singular points on the ceiling's edges.
        EXPECT_LT(percentile(displayErrors, 0.5), 2e-5) << "G o F median";
        EXPECT_LT(percentile(displayErrors, 0.99), 5e-4) << "G o F p99";
        EXPECT_LT(percentile(displayErrors, 1.0), 1e-2) << "G o F max";
        EXPECT_LT(percentile(sceneErrors, 0.5), 2e-5) << "F o G median";
        EXPECT_LT(percentile(sceneErrors, 0.99), 5e-4) << "F o G p99";
        EXPECT_LT(percentile(sceneErrors, 1.0), 1e-2) << "F o G max";
    }
}

TEST(ConformalMap, DisplayBoundaryGoesToTheSlit) {
    for (const ConformalMap* map : {&testing::cubeMap(), &testing::cabinMap()}) {
        const CaveBox& box = map->settings().box;
        const auto corners = ceilingCornerDirections(box);
        const glm::dvec3 zenith = glm::normalize(glm::dvec3(0.0, 0.5 * box.size.y, 0.0) - box.mapCentre);
        for (int k = 0; k < 4; ++k) {
            for (double t = 0.02; t < 0.99; t += 0.02) {
                // A point on ceiling edge k, nudged into Omega5.
                const glm::dvec3 edge = glm::normalize((1.0 - t) * corners[k] + t * corners[(k + 1) % 4]);
                const glm::dvec3 d = glm::normalize(edge - glm::dvec3(0.0, 1e-9, 0.0));
                ASSERT_FALSE(isMissingDirection(box, d));
                const glm::dvec3 scene = map->sceneFromDisplay(d);
                // Angle from the nearest slit arc (zenith to a corner) and whether the image
                // falls within the arc's span.
                double nearest = 10.0;
                for (const auto& corner : corners) {
                    const glm::dvec3 normal = glm::normalize(glm::cross(zenith, corner));
                    const bool isWithinArc = glm::dot(scene, corner) > glm::dot(zenith, corner) - 1e-9 &&
                                             glm::dot(scene, zenith) > glm::dot(corner, zenith) - 1e-9;
                    if (isWithinArc) nearest = std::min(nearest, std::asin(std::abs(glm::dot(scene, normal))));
                }
                // Looser next to the singular points: the corners (slit tips) and the middle
                // of the edge, where the zenith lands.
                const bool isNearSingular = t < 0.15 || t > 0.85 || std::abs(t - 0.5) < 0.1;
                const double tolerance = isNearSingular ? 2e-3 : 1e-4;
                EXPECT_LT(nearest, tolerance) << "edge " << k << " t " << t;
            }
        }
    }
}

TEST(ConformalMap, CornersAndNadirAreFixed) {
    for (const ConformalMap* map : {&testing::cubeMap(), &testing::cabinMap()}) {
        for (const auto& corner : ceilingCornerDirections(map->settings().box)) {
            EXPECT_LT(angleBetween(map->sceneFromDisplay(corner), corner), 1e-8);
            EXPECT_LT(angleBetween(map->displayFromScene(corner), corner), 1e-8);
        }
        const glm::dvec3 nadir(0.0, -1.0, 0.0);
        EXPECT_LT(angleBetween(map->sceneFromDisplay(nadir), nadir), 1e-8);
        EXPECT_LT(angleBetween(map->displayFromScene(nadir), nadir), 1e-8);
    }
}

TEST(ConformalMap, CubeMapIsEightFoldSymmetric) {
    const ConformalMap& map = testing::cubeMap();
    const std::array<glm::dmat3, 2> generators = {
        glm::dmat3(0, 0, 1, 0, 1, 0, -1, 0, 0),  // quarter turn about +y
        glm::dmat3(-1, 0, 0, 0, 1, 0, 0, 0, 1),  // mirror x -> -x
    };
    double worst = 0.0;
    for (const glm::dvec3& d : randomDirections(2000, 5)) {
        if (isMissingDirection(map.settings().box, d)) continue;
        const glm::dvec3 image = map.sceneFromDisplay(d);
        for (const glm::dmat3& g : generators) {
            worst = std::max(worst, angleBetween(map.sceneFromDisplay(g * d), g * image));
        }
    }
    EXPECT_LT(worst, 1e-8);
}

TEST(ConformalMap, InterpolationReproducesVertexValues) {
    const ConformalMap& map = testing::cubeMap();
    const SphereMesh& display = map.displayMesh();
    for (std::size_t v = 0; v < display.mesh.positions.size(); v += 37) {
        const auto z = map.diskFromDisplay(display.mesh.positions[v]);
        EXPECT_NEAR(std::abs(z - map.displayDisk()[v]), 0.0, 1e-12);
    }
    EXPECT_THROW(map.diskFromDisplay(glm::dvec3(0.0, 1.0, 0.0)), std::domain_error);
}

}  // namespace
}  // namespace conformal
