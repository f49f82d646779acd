#include <random>
#include <set>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "conformal/sphere_mesh.h"

namespace conformal {
namespace {

/// Euler characteristic V - E + F and the number of boundary edges.
std::pair<long, long> eulerAndBoundary(const TriangleMesh& mesh) {
    const auto twins = twinHalfEdges(mesh);
    long boundary = 0;
    long interior = 0;
    for (const int twin : twins) (twin < 0 ? boundary : interior) += 1;
    const long edges = boundary + interior / 2;
    return {static_cast<long>(mesh.positions.size()) - edges + static_cast<long>(mesh.triangles.size()), boundary};
}

TEST(SphereMesh, BothDomainsAreTopologicalDisks) {
    for (const auto domain : {SphereDomain::Scene, SphereDomain::Display}) {
        const SphereMesh sphere = buildSphereMesh(CaveBox{}, domain, {16, 1.0});
        const auto [euler, boundaryEdges] = eulerAndBoundary(sphere.mesh);
        EXPECT_EQ(euler, 1);
        EXPECT_GT(boundaryEdges, 0);
        for (const auto& p : sphere.mesh.positions) EXPECT_NEAR(glm::length(p), 1.0, 1e-15);
    }
}

TEST(SphereMesh, SceneBoundaryIsTheSlit) {
    // Every boundary vertex of Omega6 lies on a ceiling diagonal: the slit's two sides.
    const CaveBox box = immersiveCabinBox();
    const SphereMesh sphere = buildSphereMesh(box, SphereDomain::Scene, {24, 1.0});
    const auto twins = twinHalfEdges(sphere.mesh);
    const auto isBoundary = boundaryVertexFlags(sphere.mesh, twins);
    for (std::size_t v = 0; v < isBoundary.size(); ++v) {
        if (!isBoundary[v]) continue;
        const glm::dvec3 d = sphere.mesh.positions[v];
        ASSERT_GT(d.y, 0.0);
        const double t = (0.5 * box.size.y - box.mapCentre.y) / d.y;
        const double x = t * d.x / (0.5 * box.size.x);
        const double z = t * d.z / (0.5 * box.size.z);
        EXPECT_NEAR(std::abs(x), std::abs(z), 1e-12);
    }
}

TEST(SphereMesh, LocatesEveryDirectionInItsTriangle) {
    const SphereMesh scene = buildSphereMesh(CaveBox{}, SphereDomain::Scene, {16, 1.5});
    const SphereMesh display = buildSphereMesh(CaveBox{}, SphereDomain::Display, {16, 1.5});
    std::mt19937 random(7);
    std::normal_distribution<double> normal;
    for (int k = 0; k < 2000; ++k) {
        const glm::dvec3 d = glm::normalize(glm::dvec3(normal(random), normal(random), normal(random)));
        const MeshLocation location = locateDirection(scene, d);
        ASSERT_GE(location.triangle, 0);
        for (int c = 0; c < 3; ++c) EXPECT_GE(location.barycentric[c], -1e-12);
        const auto& tri = scene.mesh.triangles[location.triangle];
        const glm::dvec3 p = location.barycentric.x * scene.mesh.positions[tri[0]] +
                             location.barycentric.y * scene.mesh.positions[tri[1]] +
                             location.barycentric.z * scene.mesh.positions[tri[2]];
        EXPECT_NEAR(glm::length(glm::cross(glm::normalize(p), d)), 0.0, 1e-12);
        const MeshLocation inDisplay = locateDirection(display, d);
        EXPECT_EQ(inDisplay.triangle < 0, isMissingDirection(CaveBox{}, d));
    }
}

TEST(SphereMesh, RejectsBadSettings) {
    EXPECT_THROW(buildSphereMesh(CaveBox{}, SphereDomain::Scene, {1, 1.0}), std::invalid_argument);
    EXPECT_THROW(buildSphereMesh(CaveBox{}, SphereDomain::Scene, {16, 0.5}), std::invalid_argument);
    CaveBox outside;
    outside.mapCentre = glm::dvec3(0.0, 2.0, 0.0);
    EXPECT_THROW(buildSphereMesh(outside, SphereDomain::Scene, {16, 1.0}), std::invalid_argument);
}

}  // namespace
}  // namespace conformal
