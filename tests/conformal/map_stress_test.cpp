// Numerical stress of the conformal map: Ricci flow on meshes with slivers, jittered vertices,
// tiny and large holes; boxes from a cube to 4:1; F and G exactly on cube-map seams and corners,
// on the ceiling's edge, at nadir and zenith, and on inputs that are not directions at all.
// Every case must give finite values that agree with the closed form of phi6 (where one exists)
// or with each other (G o F = identity), or stop with a clear error.
#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "conformal/conformal_map.h"
#include "conformal/cube_map.h"
#include "conformal/riemann_map.h"
#include "conformal/scene_disk_closed_form.h"
#include "conformal/sphere_mesh.h"
#include "test_maps.h"

namespace conformal {
namespace {

using Complex = std::complex<double>;

double angleBetween(const glm::dvec3& a, const glm::dvec3& b) {
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

bool isFiniteUnit(const glm::dvec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && std::abs(glm::length(v) - 1.0) < 1e-9;
}

bool isFinite(Complex z) { return std::isfinite(z.real()) && std::isfinite(z.imag()); }

/// Smallest corner angle (degrees) over the mesh's triangles, from the positions.
double smallestAngleDeg(const TriangleMesh& mesh) {
    double smallest = 180.0;
    for (const auto& tri : mesh.triangles) {
        for (int k = 0; k < 3; ++k) {
            const glm::dvec3 a = mesh.positions[tri[(k + 1) % 3]] - mesh.positions[tri[k]];
            const glm::dvec3 b = mesh.positions[tri[(k + 2) % 3]] - mesh.positions[tri[k]];
            smallest = std::min(smallest, glm::degrees(angleBetween(a, b)));
        }
    }
    return smallest;
}

/// The map's singular points: the ceiling corners and the ceiling edges' midpoints, where the
/// zenith lands (exact for square ceilings, close otherwise). The accuracy documented in
/// docs/conformal.md is quoted away from them.
double angleToSingularPoints(const CaveBox& box, const glm::dvec3& d) {
    const auto corners = ceilingCornerDirections(box);
    double nearest = 10.0;
    for (int k = 0; k < 4; ++k) {
        nearest = std::min(nearest, angleBetween(d, corners[k]));
        nearest = std::min(nearest, angleBetween(d, glm::normalize(corners[k] + corners[(k + 1) % 4])));
    }
    return nearest;
}

/// Signed area of the disk image of each triangle must be positive: a fold-over would be a map
/// that is not one to one.
int foldedTriangles(const TriangleMesh& mesh, const std::vector<Complex>& disk) {
    int folded = 0;
    for (const auto& tri : mesh.triangles) {
        const Complex e1 = disk[tri[1]] - disk[tri[0]];
        const Complex e2 = disk[tri[2]] - disk[tri[0]];
        folded += (e1.real() * e2.imag() - e1.imag() * e2.real()) <= 0.0 ? 1 : 0;
    }
    return folded;
}

/// |phi6| against the closed form's modulus over the vertices off the slit. diskFromMesh leaves
/// the disk's rotation free, and for the cube symmetry puts the nadir on 0, so the modulus is
/// an oracle that needs no alignment.
struct ModulusError {
    double mean = 0.0;
    double max = 0.0;
};
ModulusError modulusErrorAgainstClosedForm(const SphereMesh& sphere, const std::vector<Complex>& disk) {
    ModulusError error;
    int count = 0;
    for (std::size_t v = 0; v < disk.size(); ++v) {
        if (sphere.slitSector[v] >= 0) continue;
        const double e = std::abs(std::abs(disk[v]) - std::abs(sceneDiskFromDirectionClosedForm(sphere.box, sphere.mesh.positions[v])));
        error.mean += e;
        error.max = std::max(error.max, e);
        ++count;
    }
    error.mean /= count;
    return error;
}

void expectClearFlowError(const std::exception& error) {
    const std::string message = error.what();
    EXPECT_FALSE(message.empty());
    EXPECT_EQ(message.find("nan"), std::string::npos) << message;
}

/// Random directions away from the singular points and (for the display side) off the ceiling.
std::vector<glm::dvec3> testDirections(const CaveBox& box, int count, unsigned seed, bool isDisplay) {
    std::mt19937 random(seed);
    std::normal_distribution<double> normal;
    std::vector<glm::dvec3> directions;
    while (static_cast<int>(directions.size()) < count) {
        const glm::dvec3 d = glm::normalize(glm::dvec3(normal(random), normal(random), normal(random)));
        if (angleToSingularPoints(box, d) < 0.05) continue;
        if (isDisplay && isMissingDirection(box, d)) continue;
        directions.push_back(d);
    }
    return directions;
}

double percentile(std::vector<double> values, double fraction) {
    const std::size_t k = std::min(values.size() - 1, static_cast<std::size_t>(fraction * static_cast<double>(values.size())));
    std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
    return values[k];
}

// --- Ricci flow on hard meshes ---------------------------------------------------------------

TEST(MapStress, SliverMeshesFlowToTheClosedFormOrStopClearly) {
    // Strong grading toward the box edges makes cells thousands of times longer than wide next to
    // the edges' midpoints: slivers far below 0.5 degrees, on a mesh the product could be given.
    int sliverMeshes = 0;
    // Grading 3 at resolution 24 has angles down to 0.027 degrees. (Grading 4, 0.0009 degrees,
    // still flows to the closed form, but G o F then misses by up to 2.3 rad: an open finding
    // in docs/robustness.md, not a supported mesh.)
    for (const double grading : {2.5, 3.0}) {
        ConformalMapSettings settings;
        settings.mesh.resolution = 24;
        settings.mesh.grading = grading;
        const double smallest = smallestAngleDeg(buildSphereMesh(settings.box, SphereDomain::Scene, settings.mesh).mesh);
        sliverMeshes += smallest < 0.5 ? 1 : 0;
        try {
            const ConformalMap map(settings);
            // Boundary values on the circle; interior ones inside it up to the extrapolation's
            // error next to the boundary (1e-5 measured at grading 3; before the hole fill kept
            // clear of the boundary, values reached 2 % outside and F returned NaN).
            for (const Complex& z : map.sceneDisk()) ASSERT_TRUE(isFinite(z) && std::abs(z) <= 1.0 + 1e-4);
            for (const Complex& z : map.displayDisk()) ASSERT_TRUE(isFinite(z) && std::abs(z) <= 1.0 + 1e-4);
            EXPECT_EQ(foldedTriangles(map.sceneMesh().mesh, map.sceneDisk()), 0) << "grading " << grading;
            EXPECT_EQ(foldedTriangles(map.displayMesh().mesh, map.displayDisk()), 0) << "grading " << grading;
            // The closed form of phi6: the mesh's slivers must not spoil the map. At this
            // resolution the graded default (p = 1.75) is pre-asymptotic with mean errors of
            // 1e-3 .. 1e-2 (docs/conformal.md); 2e-2 allows for the coarser face centres.
            double sum = 0.0;
            for (std::size_t v = 0; v < map.sceneDisk().size(); ++v) {
                if (map.sceneMesh().slitSector[v] >= 0) continue;
                sum += std::abs(map.sceneDisk()[v] - sceneDiskFromDirectionClosedForm(settings.box, map.sceneMesh().mesh.positions[v]));
            }
            const double mean = sum / static_cast<double>(map.sceneDisk().size());
            std::cout << "grading " << grading << (map.report().isDisplayExtrapolated ? "" : " (display kept unextrapolated)")
                      << ": smallest angle " << smallest << " deg, mean |phi6 - closed form| "
                      << mean << "\n";
            EXPECT_LT(mean, 2e-2) << "grading " << grading;
            for (const glm::dvec3& d : testDirections(settings.box, 200, 11, true)) {
                const glm::dvec3 scene = map.sceneFromDisplay(d);
                ASSERT_TRUE(isFiniteUnit(scene));
                EXPECT_LT(angleBetween(map.displayFromScene(scene), d), 2e-2) << "grading " << grading;
            }
        } catch (const std::runtime_error& error) {
            std::cout << "grading " << grading << ": smallest angle " << smallest << " deg, stopped: " << error.what() << "\n";
            expectClearFlowError(error);
        }
    }
    EXPECT_GT(sliverMeshes, 0) << "no mesh had a sliver under 0.5 degrees: the test tests nothing";
}

TEST(MapStress, PlanarSliversUnderATenthOfADegree) {
    // A flat disk of cells 600 times wider than tall (smallest angle 0.095 degrees): flattening
    // it must reproduce its own flat metric (u = 0 up to the boundary's turning) or stop clearly.
    TriangleMesh mesh;
    const int w = 10, h = 10;
    for (int j = 0; j <= h; ++j) {
        for (int i = 0; i <= w; ++i) mesh.positions.emplace_back(600.0 * i, j, 0.0);
    }
    for (int j = 0; j < h; ++j) {
        for (int i = 0; i < w; ++i) {
            const int a = j * (w + 1) + i;
            mesh.triangles.push_back({a, a + 1, a + w + 2});
            mesh.triangles.push_back({a, a + w + 2, a + w + 1});
        }
    }
    ASSERT_LT(smallestAngleDeg(mesh), 0.1);
    // Targets: the mesh's own curvatures (0 inside, the rectangle's turning on the boundary), so
    // u = 0 is the exact solution and any other answer is the flow's error.
    const auto isBoundary = boundaryVertexFlags(mesh, twinHalfEdges(mesh));
    std::vector<double> targets(mesh.positions.size(), 0.0);
    std::vector<double> angleSum(mesh.positions.size(), 0.0);
    for (const auto& tri : mesh.triangles) {
        std::array<double, 3> lengths{};
        std::array<double, 3> angles{};
        for (int k = 0; k < 3; ++k) lengths[k] = glm::length(mesh.positions[tri[(k + 2) % 3]] - mesh.positions[tri[(k + 1) % 3]]);
        ASSERT_TRUE(triangleAnglesFromLengths(lengths, angles));
        for (int k = 0; k < 3; ++k) angleSum[tri[k]] += angles[k];
    }
    for (std::size_t v = 0; v < targets.size(); ++v) targets[v] = (isBoundary[v] ? std::numbers::pi : 2.0 * std::numbers::pi) - angleSum[v];
    for (const auto metric : {DiscreteMetric::VertexScaling, DiscreteMetric::CirclePacking}) {
        RicciFlowSettings settings;
        settings.metric = metric;
        try {
            const RicciFlowResult result = flowToTargetCurvature(mesh, targets, settings);
            EXPECT_LT(result.maxCurvatureError, 1e-10);
            // Up to the global scale the flow pins, the metric found is the mesh's own.
            for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
                for (int k = 0; k < 3; ++k) {
                    const auto& tri = mesh.triangles[t];
                    const double original = glm::length(mesh.positions[tri[(k + 2) % 3]] - mesh.positions[tri[(k + 1) % 3]]);
                    ASSERT_NEAR(result.edgeLengths[t][k] / original, 1.0, 1e-6) << "triangle " << t;
                }
            }
        } catch (const RicciFlowError& error) {
            expectClearFlowError(error);
        }
    }
}

TEST(MapStress, JitteredVerticesKeepTheClosedForm) {
    // Every interior vertex moved at random by up to 30 % of its shortest edge: the Riemann map
    // at the moved vertices is still the closed form there, and the flow's error may grow only
    // modestly against the unjittered mesh (the second method).
    const CaveBox box;
    const SphereMesh regular = buildSphereMesh(box, SphereDomain::Scene, {24, 1.0, 1});
    SphereMesh jittered = regular;
    const auto isBoundary = boundaryVertexFlags(regular.mesh, twinHalfEdges(regular.mesh));
    std::vector<double> shortest(regular.mesh.positions.size(), 10.0);
    for (const auto& tri : regular.mesh.triangles) {
        for (int k = 0; k < 3; ++k) {
            const double l = glm::length(regular.mesh.positions[tri[k]] - regular.mesh.positions[tri[(k + 1) % 3]]);
            shortest[tri[k]] = std::min(shortest[tri[k]], l);
            shortest[tri[(k + 1) % 3]] = std::min(shortest[tri[(k + 1) % 3]], l);
        }
    }
    std::mt19937 random(7);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    for (std::size_t v = 0; v < jittered.mesh.positions.size(); ++v) {
        // The slit (the boundary) and the nadir, which diskFromMesh sends to 0, stay put.
        if (isBoundary[v] || static_cast<int>(v) == regular.nadirVertex) continue;
        glm::dvec3& p = jittered.mesh.positions[v];
        glm::dvec3 offset(uniform(random), uniform(random), uniform(random));
        offset -= glm::dot(offset, p) * p;
        if (glm::length(offset) > 0.0) p = glm::normalize(p + 0.3 * shortest[v] * offset / glm::length(offset) * std::abs(uniform(random)));
    }
    const auto regularDisk = diskFromMesh(regular.mesh, regular.nadirVertex, RicciFlowSettings{});
    const auto jitteredDisk = diskFromMesh(jittered.mesh, jittered.nadirVertex, RicciFlowSettings{});
    for (const Complex& z : jitteredDisk) ASSERT_TRUE(isFinite(z) && std::abs(z) <= 1.0 + 1e-8);
    EXPECT_EQ(foldedTriangles(jittered.mesh, jitteredDisk), 0);
    const ModulusError regularError = modulusErrorAgainstClosedForm(regular, regularDisk);
    const ModulusError jitteredError = modulusErrorAgainstClosedForm(jittered, jitteredDisk);
    std::cout << "mean | |phi6| - closed form |: regular " << regularError.mean << ", jittered " << jitteredError.mean
              << "; max " << regularError.max << ", " << jitteredError.max << "\n";
    // An irregular mesh loses the regular grid's cancellation of the leading error term: the
    // jittered error is about 5 times the regular one (measured), still far below the mesh
    // spacing (0.07 rad); 10 times flags a flow that no longer converges to the right map.
    EXPECT_LT(jitteredError.mean, 10.0 * regularError.mean);
    EXPECT_LT(jitteredError.max, 10.0 * regularError.max);
}

TEST(MapStress, TinyAndLargeHolesKeepTheClosedForm) {
    // The Riemann map punches a hole round the centre vertex and fills it back with a holomorphic
    // polynomial; its size must not matter beyond the fill's accuracy, from a hole smaller than
    // the centre's star (the default) to one of 45 degrees.
    const CaveBox box;
    const SphereMesh sphere = buildSphereMesh(box, SphereDomain::Scene, {24, 1.0, 1});
    const auto reference = diskFromMesh(sphere.mesh, sphere.nadirVertex, RicciFlowSettings{});
    const ModulusError referenceError = modulusErrorAgainstClosedForm(sphere, reference);
    for (const double holeAngle : {1e-9, 1e-3, 0.3, 0.8}) {
        try {
            RiemannMapReport report;
            const auto disk = diskFromMesh(sphere.mesh, sphere.nadirVertex, RicciFlowSettings{}, &report, holeAngle);
            for (const Complex& z : disk) ASSERT_TRUE(isFinite(z) && std::abs(z) <= 1.0 + 1e-8) << "hole " << holeAngle;
            const ModulusError error = modulusErrorAgainstClosedForm(sphere, disk);
            std::cout << "hole " << holeAngle << " rad: inner radius " << report.innerRadius << ", mean error " << error.mean
                      << " (star only: " << referenceError.mean << "), max " << error.max << "\n";
            EXPECT_LT(error.mean, 3.0 * referenceError.mean + 1e-4) << "hole " << holeAngle;
            EXPECT_LT(error.max, 3.0 * referenceError.max + 1e-3) << "hole " << holeAngle;
            EXPECT_EQ(foldedTriangles(sphere.mesh, disk), 0) << "hole " << holeAngle;
        } catch (const std::runtime_error& error) {
            std::cout << "hole " << holeAngle << " rad: stopped: " << error.what() << "\n";
            expectClearFlowError(error);
            EXPECT_GT(holeAngle, 0.5) << "a small hole must work: " << error.what();
        }
    }
    // A hole that swallows the boundary, or is not a size at all, leaves no annulus to flow.
    for (const double holeAngle : {3.0, -1.0, std::nan("")}) {
        try {
            const auto disk = diskFromMesh(sphere.mesh, sphere.nadirVertex, RicciFlowSettings{}, nullptr, holeAngle);
            for (const Complex& z : disk) ASSERT_TRUE(isFinite(z) && std::abs(z) <= 1.0 + 1e-8) << "hole " << holeAngle;
        } catch (const std::exception& error) {
            std::cout << "hole " << holeAngle << " rad: refused: " << error.what() << "\n";
            const std::string message = error.what();
            EXPECT_TRUE(message.find("Riemann map") != std::string::npos || message.find("Ricci flow") != std::string::npos)
                << message;
        }
    }
}

// --- Boxes -----------------------------------------------------------------------------------

TEST(MapStress, BoxesFromACubeToFourToOne) {
    struct Case {
        const char* name;
        glm::dvec3 size;
    };
    const Case cases[] = {
        {"cube", {2.4, 2.4, 2.4}},          {"2:1 wide", {4.8, 2.4, 2.4}}, {"4:1 wide", {9.6, 2.4, 2.4}},
        {"4:1 tall", {2.4, 9.6, 2.4}},      {"4:1 flat", {2.4, 0.6, 2.4}}, {"4:2:1", {9.6, 2.4, 4.8}},
    };
    for (const Case& c : cases) {
        ConformalMapSettings settings;
        settings.box.size = c.size;
        // At least 32 segments along the shortest edge (the resolution counts the longest), so
        // that every box is meshed as finely as the 64-segment cube's half-edges and the bounds
        // of ConformalMap.InverseComposesToIdentity apply to all of them.
        const double elongation = std::max({c.size.x, c.size.y, c.size.z}) / std::min({c.size.x, c.size.y, c.size.z});
        settings.mesh.resolution = std::max(64, static_cast<int>(std::lround(32.0 * elongation)));
        try {
            const ConformalMap map(settings);
            const CaveBox& box = map.settings().box;
            EXPECT_LT(map.report().scene.flow.maxCurvatureError, 1e-10) << c.name;
            EXPECT_LT(map.report().display.flow.maxCurvatureError, 1e-10) << c.name;
            // The alignment sector's two corners (2 and 3, the ceiling's front edge) go to fixed
            // points, so F keeps them; corners 0 and 1 only for square ceilings
            // (docs/conformal.md): their mismatch is reported, not asserted.
            const auto corners = ceilingCornerDirections(box);
            for (int k = 2; k < 4; ++k) EXPECT_LT(angleBetween(map.sceneFromDisplay(corners[k]), corners[k]), 1e-8) << c.name;
            std::cout << c.name << ": corners 0 and 1 differ between the disks by up to "
                      << map.report().tipMismatchDegrees << " degrees\n";
            std::vector<double> errors;
            for (const glm::dvec3& d : testDirections(box, 1500, 13, true)) {
                const glm::dvec3 scene = map.sceneFromDisplay(d);
                ASSERT_TRUE(isFiniteUnit(scene)) << c.name;
                const glm::dvec3 back = map.displayFromScene(scene);
                ASSERT_TRUE(isFiniteUnit(back)) << c.name;
                errors.push_back(angleBetween(back, d));
            }
            // The bounds of ConformalMap.InverseComposesToIdentity at this resolution (radians).
            std::cout << c.name << ": G o F - identity median " << percentile(errors, 0.5) << ", p99 "
                      << percentile(errors, 0.99) << ", max " << percentile(errors, 1.0) << "\n";
            // The tall box's median is 4.2e-5 (measured): its ceiling subtends 39 degrees, so
            // more of the sphere lies near the singular points; the p99 and max bounds hold.
            EXPECT_LT(percentile(errors, 0.5), c.size.y > 2.0 * c.size.x ? 5e-5 : 2e-5) << c.name;
            EXPECT_LT(percentile(errors, 0.99), 5e-4) << c.name;
            EXPECT_LT(percentile(errors, 1.0), 1e-2) << c.name;
            if (hasSceneDiskClosedForm(box)) {
                // The independent oracle for the square ceilings (tall and flat boxes too).
                double worst = 0.0;
                for (std::size_t v = 0; v < map.sceneDisk().size(); ++v) {
                    if (map.sceneMesh().slitSector[v] >= 0) continue;
                    const glm::dvec3& p = map.sceneMesh().mesh.positions[v];
                    if (angleToSingularPoints(box, p) < 0.05) continue;
                    worst = std::max(worst, std::abs(map.sceneDisk()[v] - sceneDiskFromDirectionClosedForm(box, p)));
                }
                std::cout << c.name << ": max |phi6 - closed form| away from the corners " << worst << "\n";
                EXPECT_LT(worst, 1e-3) << c.name;
            }
        } catch (const std::runtime_error& error) {
            ADD_FAILURE() << c.name << ": the map of a valid box failed: " << error.what();
        }
    }
}

TEST(MapStress, BoxesTheApiCannotMapAreRefusedClearly) {
    const auto refusal = [](const CaveBox& box) {
        ConformalMapSettings settings;
        settings.box = box;
        settings.mesh.resolution = 8;
        try {
            const ConformalMap map(settings);
        } catch (const std::invalid_argument& error) {
            return std::string(error.what());
        }
        return std::string();
    };
    CaveBox flat;
    flat.size = {2.4, 0.0, 2.4};
    EXPECT_NE(refusal(flat).find("size along axis 1"), std::string::npos);
    CaveBox onCeiling;
    onCeiling.mapCentre = {0.0, 1.2, 0.0};  // the map centre on the missing wall's plane
    EXPECT_NE(refusal(onCeiling).find("not strictly inside"), std::string::npos);
    CaveBox infinite;
    infinite.size = {INFINITY, 2.4, 2.4};
    EXPECT_NE(refusal(infinite).find("positive finite"), std::string::npos);
}

// --- Directions on seams, corners and edges ----------------------------------------------------

/// The directions where point location has ties: cube-map seams and corners (Vulkan's face
/// rules at s, t in {0, 1/2, 1}), the box's edges and corners as seen from the map centre, the
/// ceiling's edge, nadir and zenith.
std::vector<glm::dvec3> awkwardDirections(const CaveBox& box) {
    std::vector<glm::dvec3> directions;
    for (int face = 0; face < 6; ++face) {
        for (const double s : {0.0, 0.5, 1.0}) {
            for (const double t : {0.0, 0.5, 1.0}) directions.push_back(glm::normalize(directionFromCubeFace(face, s, t)));
        }
    }
    const glm::dvec3 half = 0.5 * box.size;
    for (const double x : {-1.0, 0.0, 1.0}) {
        for (const double y : {-1.0, 0.0, 1.0}) {
            for (const double z : {-1.0, 0.0, 1.0}) {
                if (x == 0.0 && y == 0.0 && z == 0.0) continue;
                directions.push_back(glm::normalize(glm::dvec3(x, y, z) * half - box.mapCentre));
            }
        }
    }
    // The ceiling's four edges, exactly (the closed ceiling square's boundary).
    for (int step = 0; step <= 8; ++step) {
        const double f = -1.0 + 0.25 * step;
        for (const glm::dvec3& p : {glm::dvec3(f * half.x, half.y, half.z), glm::dvec3(f * half.x, half.y, -half.z),
                                    glm::dvec3(half.x, half.y, f * half.z), glm::dvec3(-half.x, half.y, f * half.z)}) {
            directions.push_back(glm::normalize(p - box.mapCentre));
        }
    }
    directions.emplace_back(0.0, -1.0, 0.0);
    directions.emplace_back(0.0, 1.0, 0.0);
    return directions;
}

TEST(MapStress, SeamsCornersCeilingEdgeNadirAndZenith) {
    for (const ConformalMap* map : {&testing::cubeMap(), &testing::cabinMap()}) {
        const CaveBox& box = map->settings().box;
        std::mt19937 random(17);
        std::normal_distribution<double> normal;
        for (const glm::dvec3& d : awkwardDirections(box)) {
            const glm::dvec3 scene = map->sceneFromDisplay(d);
            const glm::dvec3 display = map->displayFromScene(d);
            ASSERT_TRUE(isFiniteUnit(scene)) << "F(" << d.x << ", " << d.y << ", " << d.z << ")";
            ASSERT_TRUE(isFiniteUnit(display)) << "G(" << d.x << ", " << d.y << ", " << d.z << ")";
            // G's values lie in the closed display domain: never inside the ceiling.
            if (isMissingDirection(box, display)) {
                double toEdge = 10.0;
                for (int k = 0; k < 4; ++k) {
                    const auto corners = ceilingCornerDirections(box);
                    const glm::dvec3 n = glm::normalize(glm::cross(corners[k], corners[(k + 1) % 4]));
                    toEdge = std::min(toEdge, std::abs(glm::dot(display, n)));
                }
                EXPECT_LT(toEdge, 1e-6) << "G(" << d.x << ", " << d.y << ", " << d.z << ") is inside the ceiling";
            }
            const bool isInsideOmega5 = !isMissingDirection(box, d);
            const double singular = angleToSingularPoints(box, d);
            if (isInsideOmega5 && singular > 0.05) {
                EXPECT_LT(angleBetween(map->displayFromScene(scene), d), 1e-2)
                    << "G o F at (" << d.x << ", " << d.y << ", " << d.z << ")";
            }
            // Continuity across the tie: F at the direction and a hair off it in any direction
            // agree. F is continuous on the closed Omega5 (its corners too: F ~ r^{3/2}); off
            // the edges' midpoints, where F ~ r^{1/2}, an offset of 1e-8 moves F by < 1e-3.
            for (int trial = 0; trial < 4; ++trial) {
                const glm::dvec3 offset = glm::normalize(glm::dvec3(normal(random), normal(random), normal(random)));
                const glm::dvec3 near = glm::normalize(d + 1e-8 * offset);
                if (isInsideOmega5 && !isMissingDirection(box, near)) {
                    EXPECT_LT(angleBetween(map->sceneFromDisplay(near), scene), 1e-3)
                        << "F jumps at (" << d.x << ", " << d.y << ", " << d.z << ")";
                }
            }
        }
        // The ceiling's edge exactly: F lands on the slit, like the edge nudged into Omega5 does.
        const auto corners = ceilingCornerDirections(box);
        for (int k = 0; k < 4; ++k) {
            for (const double t : {0.25, 0.5, 0.75}) {
                const glm::dvec3 edge = glm::normalize((1.0 - t) * corners[k] + t * corners[(k + 1) % 4]);
                const glm::dvec3 inside = glm::normalize(edge - glm::dvec3(0.0, 1e-9, 0.0));
                const double tolerance = t == 0.5 ? 2e-3 : 1e-4;  // t = 1/2: where the zenith lands
                EXPECT_LT(angleBetween(map->sceneFromDisplay(edge), map->sceneFromDisplay(inside)), tolerance)
                    << "edge " << k << " t " << t;
            }
        }
        // Nadir fixed (symmetric boxes); the zenith's scene direction goes to the boundary of
        // Omega5, within a mesh cell of one of the points where the zenith lands.
        EXPECT_LT(angleBetween(map->sceneFromDisplay(glm::dvec3(0, -1, 0)), glm::dvec3(0, -1, 0)), 1e-8);
        const glm::dvec3 zenithImage = map->displayFromScene(glm::dvec3(0, 1, 0));
        double toMidpoint = 10.0;
        for (int k = 0; k < 4; ++k) {
            toMidpoint = std::min(toMidpoint, angleBetween(zenithImage, glm::normalize(corners[k] + corners[(k + 1) % 4])));
        }
        EXPECT_LT(toMidpoint, 1e-2) << "G(zenith) lands " << toMidpoint << " rad from every edge midpoint";
    }
}

TEST(MapStress, NonDirectionsAreRefusedNotFollowed) {
    // A zero or non-finite vector has no direction: it must be refused with a clear error, not
    // followed into point location (out-of-range triangle, endless ceiling extension).
    const ConformalMap& map = testing::cubeMap();
    const double nan = std::nan("");
    for (const glm::dvec3& bad : {glm::dvec3(0.0), glm::dvec3(nan, 0.0, 1.0), glm::dvec3(INFINITY, 0.0, 0.0),
                                  glm::dvec3(0.0, -INFINITY, 1.0)}) {
        EXPECT_THROW(map.sceneFromDisplay(bad), std::invalid_argument);
        EXPECT_THROW(map.displayFromScene(bad), std::invalid_argument);
        EXPECT_THROW(map.diskFromScene(bad), std::invalid_argument);
        EXPECT_THROW(map.diskFromDisplay(bad), std::invalid_argument);
    }
    // Tiny and huge but finite vectors are directions: F is scale invariant.
    const glm::dvec3 d = glm::normalize(glm::dvec3(0.3, -0.5, 0.8));
    for (const double scale : {1e-300, 1e-160, 1e160, 1e300}) {
        EXPECT_LT(angleBetween(map.sceneFromDisplay(scale * d), map.sceneFromDisplay(d)), 1e-12) << scale;
        EXPECT_LT(angleBetween(map.displayFromScene(scale * d), map.displayFromScene(d)), 1e-12) << scale;
    }
    // Disk points: outside the closed disk the inverse maps say so with NaN (documented), and
    // absurd or non-finite points must not reach the bin index's integer conversion.
    for (const Complex z : {Complex(1e300, 0.0), Complex(-1e300, 1e300), Complex(nan, 0.0), Complex(0.0, INFINITY)}) {
        const glm::dvec3 scene = map.sceneFromDisk(z);
        const glm::dvec3 display = map.displayFromDisk(z);
        EXPECT_TRUE(std::isnan(scene.x) || isFiniteUnit(scene));
        EXPECT_TRUE(std::isnan(display.x) || isFiniteUnit(display));
    }
    EXPECT_TRUE(isFiniteUnit(map.sceneFromDisk(Complex(0.0, 0.0))));
}

}  // namespace
}  // namespace conformal
