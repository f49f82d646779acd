/// @brief Builds phi5 and phi6 by Ricci flow, aligns them, and evaluates F and G by point
/// location: sphere mesh -> disk (barycentric), disk -> other sphere mesh (barycentric).
#include "conformal/conformal_map.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <future>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>

#include "conformal/mobius_alignment.h"
#include "conformal/richardson_extrapolation.h"

namespace conformal {

namespace {

using Complex = std::complex<double>;

/// Aligns a disk map so that ceiling corners 0, 1, 2 go to 1, i, -1.
void alignCorners(std::vector<Complex>& disk, const std::array<int, 4>& corners) {
    std::array<Complex, 3> images{};
    for (int k = 0; k < 3; ++k) images[k] = disk[corners[k]] / std::abs(disk[corners[k]]);
    const Mobius align = mobiusAligningCorners(images);
    for (auto& z : disk) z = align(z);
}

std::vector<Complex> diskOfSphere(const SphereMesh& sphere, const RicciFlowSettings& flow,
                                  RiemannMapReport* report, const std::vector<double>* initialLogScale) {
    std::vector<Complex> disk = diskFromMesh(sphere.mesh, sphere.nadirVertex, flow, report, 0.0, initialLogScale);
    alignCorners(disk, sphere.cornerVertices);
    return disk;
}

/// The inverse of a Riemann map at disk point `zeta`: located in the disk mesh, then the smooth
/// interpolant or, without it, the barycentric blend of the triangle's directions. NaN outside.
glm::dvec3 sphereFromDisk(const DiskLocator& locator, const PlaneToSphereInterpolant& inverse, const TriangleMesh& mesh,
                          bool isSmooth, Complex zeta) {
    const DiskLocation location = locator.locate(zeta);
    if (location.triangle < 0) return glm::dvec3(std::numeric_limits<double>::quiet_NaN());
    if (isSmooth) return inverse.evaluate(location.triangle, location.barycentric, zeta);
    const auto& tri = mesh.triangles[location.triangle];
    const auto& p = mesh.positions;
    return glm::normalize(location.barycentric.x * p[tri[0]] + location.barycentric.y * p[tri[1]] +
                          location.barycentric.z * p[tri[2]]);
}

/// True when some triangle's disk image is not counter-clockwise (a fold-over).
bool hasFoldedTriangle(const TriangleMesh& mesh, const std::vector<Complex>& disk) {
    for (const auto& tri : mesh.triangles) {
        const Complex a = disk[tri[1]] - disk[tri[0]];
        const Complex b = disk[tri[2]] - disk[tri[0]];
        if (a.real() * b.imag() - a.imag() * b.real() <= 0.0) return true;
    }
    return false;
}

/// The unit vector of a direction given at any finite, non-zero length. A zero or non-finite
/// vector has no direction: followed into point location it found no triangle, and the
/// display side then extended "from the ceiling" forever (unbounded recursion) while the scene
/// side indexed triangle -1. Scaling by the largest component first keeps glm::normalize's
/// squares from underflowing (below ~1e-154) or overflowing (above ~1e154), so F and G stay
/// scale invariant over every finite length.
glm::dvec3 unitDirection(const glm::dvec3& v, const char* what) {
    const bool isFinite = std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
    const double largest = isFinite ? std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)}) : 0.0;
    if (!(largest > 0.0)) {
        throw std::invalid_argument(std::string("conformal map: the ") + what +
                                    " direction is zero or not finite");
    }
    return glm::normalize(v / largest);
}

}  // namespace

ConformalMap::ConformalMap(const ConformalMapSettings& settings) : mSettings(settings) {
    const auto start = std::chrono::steady_clock::now();
    validateCaveBox(settings.box);
    auto buildSide = [&settings](SphereDomain domain, SphereMesh& sphere, std::vector<Complex>& disk,
                                 RiemannMapReport* report, bool* isExtrapolated) {
        *isExtrapolated = settings.isExtrapolated;
        sphere = buildSphereMesh(settings.box, domain, settings.mesh);
        if (!settings.isExtrapolated) {
            disk = diskOfSphere(sphere, settings.flow, report, nullptr);
            return;
        }
        // The half-resolution mesh first: its flow is cheap, gives the fine flow its starting
        // point, and its map the error estimate that Richardson extrapolation removes.
        SphereMeshSettings coarseSettings = settings.mesh;
        coarseSettings.coarsening = 2;
        const SphereMesh coarse = buildSphereMesh(settings.box, domain, coarseSettings);
        RiemannMapReport coarseReport;
        const std::vector<Complex> coarseDisk = diskOfSphere(coarse, settings.flow, &coarseReport, nullptr);
        const LatticeParents parents = latticeParents(sphere, coarse);
        const std::vector<double> guess = prolongFromCoarse(parents, coarseReport.vertexLogScale);
        const std::vector<Complex> fineDisk = diskOfSphere(sphere, settings.flow, report, &guess);
        disk = extrapolateFromCoarse(parents, fineDisk, coarseDisk);
        // Richardson's step moves boundary values along chords of the circle, off it (2e-6 at
        // the default resolution, 4e-3 on coarse graded meshes); a Riemann map's boundary is
        // the unit circle, so they go back onto it.
        const std::vector<char> isBoundary = boundaryVertexFlags(sphere.mesh, twinHalfEdges(sphere.mesh));
        for (std::size_t v = 0; v < disk.size(); ++v) {
            if (isBoundary[v] && std::abs(disk[v]) > 0.0) disk[v] /= std::abs(disk[v]);
        }
        // On strongly graded meshes (slivers under 0.1 degrees) the extrapolation, with that
        // projection, folds triangles over (16 of Omega5's at grading 3, resolution 24): a map
        // that is no longer one to one is worse than the plain flow's, which is kept instead.
        if (hasFoldedTriangle(sphere.mesh, disk)) {
            disk = fineDisk;
            *isExtrapolated = false;
        }
    };
    // The two sides are independent: mesh and flow them on two threads.
    auto sceneJob = std::async(std::launch::async, [&] {
        buildSide(SphereDomain::Scene, mScene, mSceneDisk, &mReport.scene, &mReport.isSceneExtrapolated);
    });
    buildSide(SphereDomain::Display, mDisplay, mDisplayDisk, &mReport.display, &mReport.isDisplayExtrapolated);
    sceneJob.get();

    mSceneLocator = DiskLocator(mSceneDisk, mScene.mesh.triangles);
    mDisplayLocator = DiskLocator(mDisplayDisk, mDisplay.mesh.triangles);
    // Where the maps are not smooth: the ceiling corners on both sides (slit tips of Omega6,
    // reflex corners of Omega5) and the zenith's copies on the scene side.
    const auto corners = ceilingCornerDirections(settings.box);
    const glm::dvec3 zenithDirection =
        glm::normalize(glm::dvec3(0.0, 0.5 * settings.box.size.y, 0.0) - settings.box.mapCentre);
    auto chartAngle = [](const glm::dvec3& at, const glm::dvec3& toward) {
        return std::arg(SphereChart(at).chartFromDirection(toward));
    };
    std::vector<SingularPoint> sceneSingular;
    std::vector<SingularPoint> displaySingular;
    for (int k = 0; k < 4; ++k) {
        const glm::dvec3& c = corners[k];
        // The ceiling's spherical angle at corner k, between the edges to its neighbours.
        double ceilingAngle = chartAngle(c, corners[(k + 3) % 4]) - chartAngle(c, corners[(k + 1) % 4]);
        ceilingAngle = std::abs(std::remainder(ceilingAngle, 2.0 * std::numbers::pi));
        SingularPoint reflex;
        reflex.vertex = mDisplay.cornerVertices[k];
        reflex.exponent = std::numbers::pi / (2.0 * std::numbers::pi - ceilingAngle);
        reflex.wedgeAngle = chartAngle(c, zenithDirection) + std::numbers::pi;
        displaySingular.push_back(reflex);
        SingularPoint tip;
        tip.vertex = mScene.cornerVertices[k];
        tip.exponent = 0.5;
        tip.isInverseSmooth = true;
        sceneSingular.push_back(tip);
    }
    for (std::size_t v = 0; v < mScene.mesh.positions.size(); ++v) {
        if (glm::length(mScene.mesh.positions[v] - zenithDirection) > 1e-12) continue;
        // Zenith copy of sector k: the wedge between the slit arcs to corners k and k + 1.
        const int k = mScene.slitSector[v];
        double sectorAngle = chartAngle(zenithDirection, corners[(k + 1) % 4]) - chartAngle(zenithDirection, corners[k]);
        sectorAngle = std::abs(std::remainder(sectorAngle, 2.0 * std::numbers::pi));
        SingularPoint zenith;
        zenith.vertex = static_cast<int>(v);
        zenith.exponent = std::numbers::pi / sectorAngle;
        zenith.wedgeAngle = chartAngle(zenithDirection, glm::normalize(corners[k] + corners[(k + 1) % 4]));
        sceneSingular.push_back(zenith);
    }
    mIsSmooth = settings.interpolation == MeshInterpolation::HolomorphicQuadratic;
    if (mIsSmooth) {
        mSceneForward = SphereToPlaneInterpolant(mScene.mesh, mSceneDisk, sceneSingular);
        mDisplayForward = SphereToPlaneInterpolant(mDisplay.mesh, mDisplayDisk, displaySingular);
        mSceneInverse = PlaneToSphereInterpolant(mScene.mesh, mSceneDisk, sceneSingular);
        mDisplayInverse = PlaneToSphereInterpolant(mDisplay.mesh, mDisplayDisk, displaySingular);
    }
    for (int k = 0; k < 4; ++k) {
        glm::dvec3 normal = glm::normalize(glm::cross(corners[k], corners[(k + 1) % 4]));
        if (glm::dot(normal, zenithDirection) < 0.0) normal = -normal;
        mEdgeNormals[k] = normal;
    }
    mReport.sceneCorner3 = mSceneDisk[mScene.cornerVertices[3]];
    mReport.displayCorner3 = mDisplayDisk[mDisplay.cornerVertices[3]];
    mReport.sceneNadir = mSceneDisk[mScene.nadirVertex];
    mReport.displayNadir = mDisplayDisk[mDisplay.nadirVertex];
    mReport.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

Complex ConformalMap::diskFromDisplay(const glm::dvec3& displayVector) const {
    const glm::dvec3 display = unitDirection(displayVector, "display");
    const MeshLocation location = locateDirection(mDisplay, display);
    if (location.triangle < 0) {
        throw std::domain_error("conformal map: the display direction is on the ceiling, "
                                "outside Omega5");
    }
    return displayDiskAt(location, display);
}

Complex ConformalMap::displayDiskAt(const MeshLocation& location, const glm::dvec3& display) const {
    if (mIsSmooth) return mDisplayForward.evaluate(location.triangle, location.barycentric, display);
    const auto& tri = mDisplay.mesh.triangles[location.triangle];
    return location.barycentric.x * mDisplayDisk[tri[0]] +
           location.barycentric.y * mDisplayDisk[tri[1]] +
           location.barycentric.z * mDisplayDisk[tri[2]];
}

Complex ConformalMap::diskFromScene(const glm::dvec3& sceneVector) const {
    const glm::dvec3 scene = unitDirection(sceneVector, "scene");
    const MeshLocation location = locateDirection(mScene, scene);
    if (mIsSmooth) return mSceneForward.evaluate(location.triangle, location.barycentric, scene);
    const auto& tri = mScene.mesh.triangles[location.triangle];
    return location.barycentric.x * mSceneDisk[tri[0]] + location.barycentric.y * mSceneDisk[tri[1]] +
           location.barycentric.z * mSceneDisk[tri[2]];
}

glm::dvec3 ConformalMap::sceneFromDisk(Complex zeta) const {
    return sphereFromDisk(mSceneLocator, mSceneInverse, mScene.mesh, mIsSmooth, zeta);
}

glm::dvec3 ConformalMap::displayFromDisk(Complex zeta) const {
    return sphereFromDisk(mDisplayLocator, mDisplayInverse, mDisplay.mesh, mIsSmooth, zeta);
}

glm::dvec3 ConformalMap::sceneFromDisplay(const glm::dvec3& display) const {
    const glm::dvec3 d = unitDirection(display, "display");
    const MeshLocation location = locateDirection(mDisplay, d);
    if (location.triangle < 0) return ceilingExtension(d);
    return sceneFromDisk(displayDiskAt(location, d));
}

glm::dvec3 ConformalMap::displayFromScene(const glm::dvec3& scene) const {
    return displayFromDisk(diskFromScene(scene));
}

glm::dvec3 ConformalMap::ceilingExtension(const glm::dvec3& display) const {
    // Point reflection through the foot on the nearest ceiling edge: F(b + v) := 2 F(b) - F(b - v)
    // continues F with its value and normal derivative across the edge.
    int nearest = 0;
    double nearestDistance = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 4; ++k) {
        const double distance = std::abs(glm::dot(display, mEdgeNormals[k]));
        if (distance < nearestDistance) {
            nearestDistance = distance;
            nearest = k;
        }
    }
    const glm::dvec3& normal = mEdgeNormals[nearest];
    const double height = glm::dot(display, normal);
    const glm::dvec3 mirrored = display - 2.0 * height * normal;
    constexpr double kInset = 1e-9;  // moves the foot off the edge into Omega5
    const glm::dvec3 foot = glm::normalize(display - (height + kInset) * normal);
    const glm::dvec3 onEdge = sceneFromDisplay(foot);
    const glm::dvec3 across = sceneFromDisplay(mirrored);
    const glm::dvec3 extended = 2.0 * onEdge - across;
    const double length = glm::length(extended);
    return length > 1e-12 ? extended / length : onEdge;
}

}  // namespace conformal
