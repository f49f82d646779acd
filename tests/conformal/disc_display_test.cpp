// Displays other than the 5-wall cabin: which sets of walls the map accepts, the domain and slit
// it builds for them, and the classic 4-wall CAVE's map (ceiling and back missing): boundary onto
// the slit, aligned corners kept, conformal by differences of its bake, mirror symmetric.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <numbers>
#include <random>
#include <set>
#include <string>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "conformal/cube_map_baker.h"
#include "conformal/distortion.h"
#include "conformal/linear_map.h"
#include "conformal/triangle_mesh.h"
#include "test_maps.h"

namespace conformal {
namespace {

constexpr int kRight = 0, kLeft = 1, kCeiling = 2, kFloor = 3, kBack = 4, kFront = 5;

double angleBetween(const glm::dvec3& a, const glm::dvec3& b) {
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

CaveBox boxLacking(std::uint32_t faces) {
    CaveBox box;
    box.missingFaces = faces;
    return box;
}

std::string refusal(const CaveBox& box) {
    try {
        validateCaveBox(box);
    } catch (const std::invalid_argument& error) {
        return error.what();
    }
    return "";
}

/// V - E + F of a triangle mesh and its number of boundary loops.
std::pair<long, int> eulerAndBoundaryLoops(const TriangleMesh& mesh) {
    std::set<std::pair<int, int>> edges;
    std::map<int, int> boundaryNext;  // each boundary half-edge's start to its end
    std::set<std::pair<int, int>> halfEdges;
    for (const auto& t : mesh.triangles) {
        for (int k = 0; k < 3; ++k) {
            const int a = t[k], b = t[(k + 1) % 3];
            edges.insert({std::min(a, b), std::max(a, b)});
            halfEdges.insert({a, b});
        }
    }
    for (const auto& [a, b] : halfEdges) {
        if (halfEdges.count({b, a}) == 0) boundaryNext[a] = b;
    }
    int loops = 0;
    std::set<int> visited;
    for (const auto& [start, next] : boundaryNext) {
        if (visited.count(start) != 0) continue;
        ++loops;
        for (int v = start; visited.insert(v).second; v = boundaryNext.at(v)) {
        }
    }
    const long euler = static_cast<long>(mesh.positions.size()) - static_cast<long>(edges.size()) +
                       static_cast<long>(mesh.triangles.size());
    return {euler, loops};
}

/// Angle from `p` to the slit (the great-circle arcs between consecutive points of its runs).
double angleToSlit(const SphereMesh& scene, const glm::dvec3& p) {
    const glm::dvec3 centre = scene.box.mapCentre;
    const auto direction = [&](const SlitSegment& run, int k) {
        const glm::dvec3 point(scene.gridLines[0][run.from[0] + k * run.step[0]],
                               scene.gridLines[1][run.from[1] + k * run.step[1]],
                               scene.gridLines[2][run.from[2] + k * run.step[2]]);
        return glm::normalize(point - centre);
    };
    double nearest = 10.0;
    for (const SlitSegment& run : scene.slit) {
        for (int k = 0; k < run.steps; ++k) {
            const glm::dvec3 a = direction(run, k), b = direction(run, k + 1);
            const glm::dvec3 normal = glm::normalize(glm::cross(a, b));
            const glm::dvec3 inPlane = glm::normalize(p - glm::dot(p, normal) * normal);
            const bool isBetween = glm::dot(glm::cross(a, inPlane), normal) >= 0.0 &&
                                   glm::dot(glm::cross(inPlane, b), normal) >= 0.0;
            nearest = std::min(nearest, isBetween ? std::abs(std::asin(std::clamp(glm::dot(p, normal), -1.0, 1.0)))
                                                  : std::min(angleBetween(p, a), angleBetween(p, b)));
        }
    }
    return nearest;
}

/// cave4's missing walls on the lattice: the ceiling's plane (top y) or the back's (last z),
/// boundary included (rounding puts some edge directions on either side of the closed test).
bool isOnCave4MissingWall(const SphereMesh& sphere, std::size_t v) {
    const auto& at = sphere.lattice[v];
    return at[1] == static_cast<int>(sphere.gridLines[1].size()) - 1 ||
           at[2] == static_cast<int>(sphere.gridLines[2].size()) - 1;
}

TEST(DiscDisplays, WallSetsThatAreNotADiscAreRefusedByName) {
    EXPECT_EQ(refusal(boxLacking(faceBit(kCeiling))), "");
    EXPECT_EQ(refusal(testing::cave4Box()), "");
    EXPECT_EQ(refusal(boxLacking(faceBit(kCeiling) | faceBit(kBack) | faceBit(kFloor))), "");  // a band
    EXPECT_EQ(refusal(boxLacking(faceBit(kCeiling) | faceBit(kBack) | faceBit(kLeft))), "");   // around a corner
    // Only two opposite walls present: the missing walls are a ring, the present ones in pieces.
    EXPECT_NE(refusal(boxLacking(faceBit(kCeiling) | faceBit(kFloor) | faceBit(kBack) | faceBit(kFront)))
                  .find("present walls (right, left) are in pieces"),
              std::string::npos);
    // Two opposite missing walls leave an annulus of directions.
    EXPECT_NE(refusal(boxLacking(faceBit(kCeiling) | faceBit(kFloor))).find("missing walls (ceiling, floor) are not connected"),
              std::string::npos);
    EXPECT_NE(refusal(boxLacking(0)).find("no wall is missing"), std::string::npos);
    EXPECT_NE(refusal(boxLacking(63)).find("every wall is missing"), std::string::npos);
    // One present wall: a disc, but no corner where the slit could end.
    EXPECT_NE(refusal(boxLacking(63 & ~faceBit(kFloor))).find("fewer than two corners"), std::string::npos);
    EXPECT_THROW(buildSphereMesh(boxLacking(faceBit(kCeiling) | faceBit(kFloor)), SphereDomain::Display, {}),
                 std::invalid_argument);
}

TEST(DiscDisplays, Cave4DomainIsADiscWithItsCornersWhereTheWallsSay) {
    const CaveBox box = testing::cave4Box();
    // Corners: bit 1 +x, 2 +y, 4 +z. The ceiling's front corners and the back's bottom corners
    // touch one missing wall (reflex, the slit's tips); the ceiling's back corners two (convex).
    EXPECT_EQ(slitTipCorners(box), (std::vector<int>{1 | 4, 4, 2, 1 | 2}));  // by azimuth
    EXPECT_EQ(boundaryCorners(box), (std::vector<int>{2, 1 | 2, 4, 1 | 4, 2 | 4, 1 | 2 | 4}));
    SphereMeshSettings settings;
    settings.resolution = 32;
    for (const SphereDomain domain : {SphereDomain::Display, SphereDomain::Scene}) {
        const SphereMesh sphere = buildSphereMesh(box, domain, settings);
        const auto [euler, loops] = eulerAndBoundaryLoops(sphere.mesh);
        EXPECT_EQ(euler, 1) << (domain == SphereDomain::Display ? "Omega5" : "Omega6");
        EXPECT_EQ(loops, 1);
        ASSERT_EQ(sphere.cornerVertices.size(), 4u);
        EXPECT_EQ(sphere.sectorTips.size(), 4u);
        for (std::size_t k = 0; k < 4; ++k) {
            EXPECT_LT(angleBetween(sphere.mesh.positions[sphere.cornerVertices[k]],
                                   boxCornerDirection(box, slitTipCorners(box)[k])),
                      1e-12);
        }
    }
    // Omega5's boundary vertices are exactly its vertices on a missing wall (its edges): on the
    // lattice, the ceiling's top plane or the back's plane.
    const SphereMesh display = buildSphereMesh(box, SphereDomain::Display, settings);
    const std::vector<char> isBoundary = boundaryVertexFlags(display.mesh, twinHalfEdges(display.mesh));
    for (std::size_t v = 0; v < display.mesh.positions.size(); ++v) {
        EXPECT_EQ(static_cast<bool>(isBoundary[v]), isOnCave4MissingWall(display, v)) << v;
    }
}

TEST(DiscDisplays, SlitIsTheCrossForTheCabinAndAnHForCave4) {
    SphereMeshSettings settings;
    settings.resolution = 32;
    // The cabin: four half-diagonals of the ceiling from its centre, one per corner.
    const SphereMesh cabin = buildSphereMesh(immersiveCabinBox(), SphereDomain::Scene, settings);
    ASSERT_EQ(cabin.slit.size(), 4u);
    for (const SlitSegment& run : cabin.slit) {
        EXPECT_EQ(run.step[1], 0);
        EXPECT_EQ(std::abs(run.step[0]) + std::abs(run.step[2]), 2);  // diagonal
        EXPECT_EQ(run.from, (std::array<int, 3>{16, static_cast<int>(cabin.gridLines[1].size()) - 1, 16}));
    }
    // cave4: two half-diagonals on the ceiling, two on the back, and the spine between the two
    // faces' centres through the midpoint of their shared edge (the medial axis of the
    // unfolded 1 x 2 rectangle).
    const SphereMesh cave4 = buildSphereMesh(testing::cave4Box(), SphereDomain::Scene, settings);
    ASSERT_EQ(cave4.slit.size(), 6u);
    int diagonals = 0, spines = 0;
    for (const SlitSegment& run : cave4.slit) {
        const int moving = (run.step[0] != 0) + (run.step[1] != 0) + (run.step[2] != 0);
        diagonals += moving == 2;
        spines += moving == 1;
        EXPECT_EQ(run.steps, 16);
    }
    EXPECT_EQ(diagonals, 4);
    EXPECT_EQ(spines, 2);
    // Every point of the missing walls off the slit belongs to one sector, every slit copy too.
    for (std::size_t v = 0; v < cave4.mesh.positions.size(); ++v) {
        const bool isMissing = isOnCave4MissingWall(cave4, v);
        const bool isTip = std::find(cave4.cornerVertices.begin(), cave4.cornerVertices.end(), static_cast<int>(v)) !=
                           cave4.cornerVertices.end();
        if (isMissing && !isTip) {
            EXPECT_GE(cave4.missingSector[v], 0) << v;
        } else if (!isMissing) {
            EXPECT_EQ(cave4.missingSector[v], -1) << v;
        }
    }
}

/// Angles from F's images of Omega5's boundary vertices to the slit.
std::vector<double> boundaryOffSlit(const ConformalMap& map) {
    const SphereMesh& display = map.displayMesh();
    const std::vector<char> isBoundary = boundaryVertexFlags(display.mesh, twinHalfEdges(display.mesh));
    std::vector<double> angles;
    for (std::size_t v = 0; v < display.mesh.positions.size(); ++v) {
        if (isBoundary[v]) angles.push_back(angleToSlit(map.sceneMesh(), map.sceneFromDisplay(display.mesh.positions[v])));
    }
    std::sort(angles.begin(), angles.end());
    return angles;
}

TEST(DiscDisplays, Cave4MapSendsTheBoundaryOntoTheSlitAndKeepsTheAlignedCorners) {
    const ConformalMap& map = testing::cave4Map();
    // Boundary vertices go onto the slit up to the interpolation of phi6^-1 between the disk's
    // boundary chords (O(h^2): the cube's cabin map at the same resolution for scale).
    const std::vector<double> cave4 = boundaryOffSlit(map);
    const std::vector<double> cube = boundaryOffSlit(testing::cubeMap());
    std::printf("boundary to slit (rad): cave4 median %.2e max %.2e; cube median %.2e max %.2e\n",
                cave4[cave4.size() / 2], cave4.back(), cube[cube.size() / 2], cube.back());
    EXPECT_GT(cave4.size(), 300u);
    EXPECT_LT(cave4[cave4.size() / 2], 1e-5);
    EXPECT_LT(cave4.back(), 3e-4);
    // Directions 3 degrees or more inside the display domain land off the slit.
    std::mt19937 random(3);
    std::normal_distribution<double> normal;
    int inside = 0;
    for (int k = 0; k < 400; ++k) {
        const glm::dvec3 d = glm::normalize(glm::dvec3(normal(random), normal(random), normal(random)));
        const glm::dvec3 u = glm::normalize(glm::cross(d, glm::dvec3(0.3, 0.5, 0.7)));
        const glm::dvec3 w = glm::cross(d, u);
        bool isInside = !isMissingDirection(map.settings().box, d);
        for (int a = 0; a < 8 && isInside; ++a) {
            const double angle = a * std::numbers::pi / 4.0;
            const glm::dvec3 around = glm::normalize(d + std::tan(0.05) * (std::cos(angle) * u + std::sin(angle) * w));
            isInside = !isMissingDirection(map.settings().box, around);
        }
        if (!isInside) continue;
        ++inside;
        EXPECT_GT(angleToSlit(map.sceneMesh(), map.sceneFromDisplay(d)), 1e-4);
    }
    EXPECT_GT(inside, 100);
    // The alignment sector (the ceiling's front triangle) keeps its two tips and sends the
    // middle of the ceiling's front edge to the ceiling's centre.
    const auto& tips = map.sceneMesh().sectorTips[map.report().alignmentSector];
    const std::vector<int> corners = slitTipCorners(map.settings().box);
    EXPECT_EQ(corners[tips[0]] & 4, 0);  // front corners (-z)
    EXPECT_EQ(corners[tips[1]] & 4, 0);
    for (const int k : tips) {
        const glm::dvec3 corner = boxCornerDirection(map.settings().box, corners[k]);
        EXPECT_LT(angleBetween(map.sceneFromDisplay(corner), corner), 1e-8);
    }
    EXPECT_LT(angleBetween(map.sceneFromDisplay(glm::dvec3(0.0, 1.0, -1.0)), glm::dvec3(0.0, 1.0, 0.0)), 1e-7);
    // The back's bottom corners are not aligned: their mismatch is reported.
    EXPECT_GT(map.report().tipMismatchDegrees, 0.1);
    EXPECT_LT(map.report().tipMismatchDegrees, 20.0);
}

TEST(DiscDisplays, Cave4MapIsMirrorSymmetricAndInvertible) {
    const ConformalMap& map = testing::cave4Map();
    const CaveBox& box = map.settings().box;
    std::mt19937 random(7);
    std::normal_distribution<double> normal;
    double asymmetry = 0.0;
    std::vector<double> inverse;
    for (int k = 0; k < 3000; ++k) {
        const glm::dvec3 d = glm::normalize(glm::dvec3(normal(random), normal(random), normal(random)));
        if (isMissingDirection(box, d)) continue;
        const glm::dvec3 mirror(-1.0, 1.0, 1.0);
        asymmetry = std::max(asymmetry, angleBetween(map.sceneFromDisplay(mirror * d), mirror * map.sceneFromDisplay(d)));
        double nearestCorner = 10.0;
        for (const int c : boundaryCorners(box)) nearestCorner = std::min(nearestCorner, angleBetween(d, boxCornerDirection(box, c)));
        if (nearestCorner > 3.0 * std::numbers::pi / 180.0) {
            inverse.push_back(angleBetween(map.displayFromScene(map.sceneFromDisplay(d)), d));
        }
    }
    EXPECT_LT(asymmetry, 1e-8);
    const std::size_t p99 = inverse.size() * 99 / 100;
    std::nth_element(inverse.begin(), inverse.begin() + static_cast<std::ptrdiff_t>(p99), inverse.end());
    EXPECT_LT(inverse[p99] * 180.0 / std::numbers::pi, 1e-2);
}

TEST(DiscDisplays, Cave4BakeIsConformalByDifferencesAndTheLinearBaselineIsNot) {
    const CaveBox box = testing::cave4Box();
    const CubeMap conformal = bakeCubeMap(testing::cave4Map(), box, MapKind::Conformal, 128);
    const DistortionStatistics stats = distortionStatistics(conformal, 5.0);
    EXPECT_GT(stats.texelCount, 50000);
    EXPECT_LT(stats.meanK - 1.0, 5e-3);
    EXPECT_LT(stats.p99K - 1.0, 5e-2);
    EXPECT_EQ(stats.foldedTexels, 0);
    const CubeMap linear = bakeCubeMap(LinearMap(box), box, MapKind::Linear, 128);
    EXPECT_GT(distortionStatistics(linear, 5.0).meanK, 2.0);
    // A display without a floor has no nadir for the linear map to scale from.
    EXPECT_THROW(LinearMap(boxLacking(faceBit(kFloor) | faceBit(kBack))), std::invalid_argument);
    // The file records the missing walls.
    const auto path = std::filesystem::temp_directory_path() / "cvc_cave4_map.cvcm";
    CubeMap small = bakeCubeMap(testing::cave4Map(), box, MapKind::Conformal, 8);
    saveCubeMap(small, path);
    EXPECT_EQ(loadCubeMap(path).box.missingFaces, box.missingFaces);
    std::filesystem::remove(path);
    (void)kRight;
}

TEST(DiscDisplays, OtherWallSetsGetAMapThatNeitherFoldsNorTears) {
    // Three walls in a row missing (a band), three around a corner, and four (only the front
    // and the floor present): each gets its slit, its sectors and a map that is one to one.
    const std::uint32_t sets[] = {faceBit(kCeiling) | faceBit(kBack) | faceBit(kFloor),
                                  faceBit(kCeiling) | faceBit(kBack) | faceBit(kLeft),
                                  faceBit(kCeiling) | faceBit(kBack) | faceBit(kLeft) | faceBit(kRight)};
    for (const std::uint32_t missing : sets) {
        ConformalMapSettings settings;
        settings.box = boxLacking(missing);
        settings.mesh.resolution = 32;
        const ConformalMap map(settings);
        const std::string name = boxFaceNames(missing);
        EXPECT_EQ(map.sceneMesh().sectorTips.size(), map.sceneMesh().cornerVertices.size()) << name;
        const DistortionStatistics stats = distortionStatistics(bakeCubeMap(map, settings.box, MapKind::Conformal, 64), 5.0);
        EXPECT_EQ(stats.foldedTexels, 0) << name;
        EXPECT_LT(stats.meanK - 1.0, 2e-2) << name;
        std::mt19937 random(5);
        std::normal_distribution<double> normal;
        std::vector<double> inverse;
        for (int k = 0; k < 1000; ++k) {
            const glm::dvec3 d = glm::normalize(glm::dvec3(normal(random), normal(random), normal(random)));
            if (!isMissingDirection(settings.box, d)) inverse.push_back(angleBetween(map.displayFromScene(map.sceneFromDisplay(d)), d));
        }
        std::sort(inverse.begin(), inverse.end());
        EXPECT_LT(inverse[inverse.size() / 2] * 180.0 / std::numbers::pi, 1e-2) << name;
    }
}

}  // namespace
}  // namespace conformal
