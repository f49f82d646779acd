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

/// The sector whose points the alignment fixes: the one owning the boundary point of the
/// display domain nearest the front wall's centre (for the cabin the ceiling's front triangle).
int alignmentSectorOf(const SphereMesh& display) {
    const glm::dvec3 front =
        glm::normalize(glm::dvec3(0.0, 0.0, -0.5 * display.box.size.z) - display.box.mapCentre);
    int sector = -1;
    double best = -2.0;
    for (std::size_t v = 0; v < display.mesh.positions.size(); ++v) {
        if (display.missingSector[v] < 0) continue;
        const double closeness = glm::dot(display.mesh.positions[v], front);
        if (closeness > best) {
            best = closeness;
            sector = display.missingSector[v];
        }
    }
    if (sector < 0) throw std::logic_error("conformal map: the display mesh has no boundary");
    return sector;
}

/// The three vertices the alignment fixes: the sector's two tips and, between them, the point
/// as far from one as from the other: on Omega5 the middle of the sector's boundary edges, on
/// Omega6 the middle of its side of the slit (for a mirror-symmetric sector the two correspond,
/// so the aligned F keeps the mirror symmetry).
std::array<int, 3> alignmentVertices(const SphereMesh& sphere, int sector) {
    const int tipA = sphere.cornerVertices[sphere.sectorTips[sector][0]];
    const int tipB = sphere.cornerVertices[sphere.sectorTips[sector][1]];
    const auto& p = sphere.mesh.positions;
    auto angle = [](const glm::dvec3& u, const glm::dvec3& v) {
        return std::atan2(glm::length(glm::cross(u, v)), glm::dot(u, v));
    };
    int middle = -1;
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t v = 0; v < p.size(); ++v) {
        const bool isCandidate = sphere.domain == SphereDomain::Scene ? sphere.slitSector[v] == sector
                                                                      : sphere.missingSector[v] == sector;
        if (!isCandidate) continue;
        const double imbalance = std::abs(angle(p[v], p[tipA]) - angle(p[v], p[tipB]));
        if (imbalance < best) {
            best = imbalance;
            middle = static_cast<int>(v);
        }
    }
    if (middle < 0) throw std::logic_error("conformal map: the alignment sector has no middle vertex");
    return {tipA, middle, tipB};
}

/// True when a, m, b follow each other counter-clockwise on the unit circle.
bool isCounterClockwise(Complex a, Complex m, Complex b) {
    const double twoPi = 2.0 * std::numbers::pi;
    const double toMiddle = std::fmod(std::arg(m / a) + twoPi, twoPi);
    const double toEnd = std::fmod(std::arg(b / a) + twoPi, twoPi);
    return toMiddle < toEnd;
}

/// Aligns a disk map: the sector's tips and middle (in counter-clockwise order) go to -1,
/// e^{-3 i pi / 4} and -i, where the paper's alignment of the cabin (ceiling corners 0, 1, 2 to
/// 1, i, -1) puts its corners 2 and 3 and the middle of the ceiling's front edge. Returns
/// whether the sector's tips had to be swapped to be counter-clockwise.
bool alignCorners(std::vector<Complex>& disk, const SphereMesh& sphere, int sector) {
    std::array<int, 3> points = alignmentVertices(sphere, sector);
    std::array<Complex, 3> images{};
    for (int k = 0; k < 3; ++k) images[k] = disk[points[k]] / std::abs(disk[points[k]]);
    const bool isSwapped = !isCounterClockwise(images[0], images[1], images[2]);
    if (isSwapped) std::swap(images[0], images[2]);
    const Mobius align = mobiusFromThreePoints(
        images, {Complex(-1.0, 0.0), std::polar(1.0, -0.75 * std::numbers::pi), Complex(0.0, -1.0)});
    for (auto& z : disk) z = align(z);
    return isSwapped;
}

bool diskOfSphere(const SphereMesh& sphere, int sector, const RicciFlowSettings& flow, RiemannMapReport* report,
                  const std::vector<double>* initialLogScale, std::vector<Complex>& disk) {
    disk = diskFromMesh(sphere.mesh, sphere.nadirVertex, flow, report, 0.0, initialLogScale);
    return alignCorners(disk, sphere, sector);
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
    mDisplay = buildSphereMesh(settings.box, SphereDomain::Display, settings.mesh);
    const int sector = alignmentSectorOf(mDisplay);
    mReport.alignmentSector = sector;
    // Builds one side on its mesh `sphere` (already built for the display side); returns whether
    // the alignment swapped the sector's tips.
    auto buildSide = [&settings, sector](SphereDomain domain, SphereMesh& sphere, std::vector<Complex>& disk,
                                         RiemannMapReport* report, bool* isExtrapolated) {
        *isExtrapolated = settings.isExtrapolated;
        if (domain == SphereDomain::Scene) sphere = buildSphereMesh(settings.box, domain, settings.mesh);
        if (!settings.isExtrapolated) return diskOfSphere(sphere, sector, settings.flow, report, nullptr, disk);
        // The half-resolution mesh first: its flow is cheap, gives the fine flow its starting
        // point, and its map the error estimate that Richardson extrapolation removes.
        SphereMeshSettings coarseSettings = settings.mesh;
        coarseSettings.coarsening = 2;
        const SphereMesh coarse = buildSphereMesh(settings.box, domain, coarseSettings);
        RiemannMapReport coarseReport;
        std::vector<Complex> coarseDisk;
        diskOfSphere(coarse, sector, settings.flow, &coarseReport, nullptr, coarseDisk);
        const LatticeParents parents = latticeParents(sphere, coarse);
        const std::vector<double> guess = prolongFromCoarse(parents, coarseReport.vertexLogScale);
        std::vector<Complex> fineDisk;
        const bool isSwapped = diskOfSphere(sphere, sector, settings.flow, report, &guess, fineDisk);
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
        return isSwapped;
    };
    // The two sides are independent: mesh and flow them on two threads.
    auto sceneJob = std::async(std::launch::async, [&] {
        return buildSide(SphereDomain::Scene, mScene, mSceneDisk, &mReport.scene, &mReport.isSceneExtrapolated);
    });
    const bool isDisplaySwapped =
        buildSide(SphereDomain::Display, mDisplay, mDisplayDisk, &mReport.display, &mReport.isDisplayExtrapolated);
    if (sceneJob.get() != isDisplaySwapped) {
        throw std::logic_error("conformal map: the two disks order the alignment sector's tips differently");
    }

    mSceneLocator = DiskLocator(mSceneDisk, mScene.mesh.triangles);
    mDisplayLocator = DiskLocator(mDisplayDisk, mDisplay.mesh.triangles);
    auto chartAngle = [](const glm::dvec3& at, const glm::dvec3& toward) {
        return std::arg(SphereChart(at).chartFromDirection(toward));
    };
    const double twoPi = 2.0 * std::numbers::pi;
    auto ccwFrom = [twoPi](double from, double to) { return std::fmod(to - from + 2.0 * twoPi, twoPi); };
    // The wedge between sorted arm angles that holds `inside`: its start and width.
    auto wedgeHolding = [&](std::vector<double> arms, double inside) {
        std::sort(arms.begin(), arms.end());
        for (std::size_t k = 0; k < arms.size(); ++k) {
            const double from = arms[k];
            const double width = arms.size() == 1 ? twoPi : ccwFrom(from, arms[(k + 1) % arms.size()]);
            if (ccwFrom(from, inside) < width) return std::pair<double, double>(from, width);
        }
        return std::pair<double, double>(arms.front(), twoPi);
    };
    const CaveBox& box = settings.box;
    auto vertexAtCorner = [](const SphereMesh& sphere, const glm::dvec3& direction) {
        for (std::size_t v = 0; v < sphere.mesh.positions.size(); ++v) {
            if (sphere.slitSector[v] < 0 && glm::length(sphere.mesh.positions[v] - direction) < 1e-12) {
                return static_cast<int>(v);
            }
        }
        throw std::logic_error("conformal map: a box corner is not a mesh vertex");
    };

    // Where the maps are not smooth. On the display side the boundary's corners: the visible
    // wedge between the two boundary edges there (reflex where one face is missing, convex
    // where two are).
    std::vector<SingularPoint> sceneSingular;
    std::vector<SingularPoint> displaySingular;
    for (const int corner : boundaryCorners(box)) {
        const glm::dvec3 c = boxCornerDirection(box, corner);
        std::vector<double> arms;
        for (int axis = 0; axis < 3; ++axis) {
            // The box edge from this corner along `axis` lies on the two faces at the corner of
            // the other axes; it bounds the display domain when exactly one of them is missing.
            const auto faces = facesAtCorner(corner);
            const int missing = (isFaceMissing(box, faces[(axis + 1) % 3]) ? 1 : 0) +
                                (isFaceMissing(box, faces[(axis + 2) % 3]) ? 1 : 0);
            if (missing == 1) arms.push_back(chartAngle(c, boxCornerDirection(box, corner ^ (1 << axis))));
        }
        int presentFace = -1;
        for (const int face : facesAtCorner(corner)) {
            if (!isFaceMissing(box, face)) presentFace = face;
        }
        glm::dvec3 faceCentre(0.0);
        faceCentre[presentFace / 2] = (presentFace % 2 == 0 ? 0.5 : -0.5) * box.size[presentFace / 2];
        const auto [from, width] = wedgeHolding(arms, chartAngle(c, glm::normalize(faceCentre - box.mapCentre)));
        SingularPoint point;
        point.vertex = vertexAtCorner(mDisplay, c);
        point.exponent = std::numbers::pi / width;
        point.wedgeAngle = from + 0.5 * width;
        displaySingular.push_back(point);
    }
    // On the scene side the slit's tips, and its copies of points where the slit branches or
    // bends: there each copy's wedge between two of the slit's arms.
    for (const int v : mScene.cornerVertices) {
        SingularPoint tip;
        tip.vertex = v;
        tip.exponent = 0.5;
        tip.isInverseSmooth = true;
        sceneSingular.push_back(tip);
    }
    std::vector<std::vector<int>> trianglesOfVertex(mScene.mesh.positions.size());
    for (std::size_t t = 0; t < mScene.mesh.triangles.size(); ++t) {
        for (const int v : mScene.mesh.triangles[t]) trianglesOfVertex[v].push_back(static_cast<int>(t));
    }
    for (std::size_t v = 0; v < mScene.mesh.positions.size(); ++v) {
        if (mScene.slitSector[v] < 0) continue;
        const auto& at = mScene.lattice[v];
        const glm::dvec3 p = mScene.mesh.positions[v];
        std::vector<double> arms;
        for (const SlitSegment& run : mScene.slit) {
            for (int k = 0; k <= run.steps; ++k) {
                const std::array<int, 3> point = {run.from[0] + k * run.step[0], run.from[1] + k * run.step[1],
                                                  run.from[2] + k * run.step[2]};
                if (point != at) continue;
                for (const int next : {k - 1, k + 1}) {
                    if (next < 0 || next > run.steps) continue;
                    const glm::dvec3 q(mScene.gridLines[0][run.from[0] + next * run.step[0]],
                                       mScene.gridLines[1][run.from[1] + next * run.step[1]],
                                       mScene.gridLines[2][run.from[2] + next * run.step[2]]);
                    arms.push_back(chartAngle(p, glm::normalize(q - box.mapCentre)));
                }
            }
        }
        const bool isStraight = arms.size() == 2 &&
                                std::abs(std::remainder(arms[0] - arms[1], twoPi)) > std::numbers::pi - 1e-9;
        if (isStraight || arms.empty()) continue;
        const auto& tri = mScene.mesh.triangles[trianglesOfVertex[v].front()];
        const glm::dvec3 inside = glm::normalize(mScene.mesh.positions[tri[0]] + mScene.mesh.positions[tri[1]] +
                                                 mScene.mesh.positions[tri[2]]);
        const auto [from, width] = wedgeHolding(arms, chartAngle(p, inside));
        SingularPoint branch;
        branch.vertex = static_cast<int>(v);
        branch.exponent = std::numbers::pi / width;
        branch.wedgeAngle = from + 0.5 * width;
        sceneSingular.push_back(branch);
    }
    mIsSmooth = settings.interpolation == MeshInterpolation::HolomorphicQuadratic;
    if (mIsSmooth) {
        mSceneForward = SphereToPlaneInterpolant(mScene.mesh, mSceneDisk, sceneSingular);
        mDisplayForward = SphereToPlaneInterpolant(mDisplay.mesh, mDisplayDisk, displaySingular);
        mSceneInverse = PlaneToSphereInterpolant(mScene.mesh, mSceneDisk, sceneSingular);
        mDisplayInverse = PlaneToSphereInterpolant(mDisplay.mesh, mDisplayDisk, displaySingular);
    }
    // The edges between missing and present faces, per missing face, for the extension.
    for (int face = 0; face < kBoxFaceCount; ++face) {
        if (!isFaceMissing(box, face)) continue;
        glm::dvec3 centre(0.0);
        centre[face / 2] = (face % 2 == 0 ? 0.5 : -0.5) * box.size[face / 2];
        const glm::dvec3 inward = glm::normalize(centre - box.mapCentre);
        for (int corner = 0; corner < 8; ++corner) {
            const auto faces = facesAtCorner(corner);
            if (std::find(faces.begin(), faces.end(), face) == faces.end()) continue;
            for (int axis = 0; axis < 3; ++axis) {
                const int other = corner ^ (1 << axis);
                if (axis == face / 2 || other < corner) continue;
                // The edge from `corner` along `axis` lies on `face` and on the face of the third axis.
                const int neighbour = faces[3 - axis - face / 2];
                if (isFaceMissing(box, neighbour)) continue;
                BoundaryEdge edge;
                edge.from = boxCornerDirection(box, corner);
                edge.to = boxCornerDirection(box, other);
                edge.normal = glm::normalize(glm::cross(edge.from, edge.to));
                if (glm::dot(edge.normal, inward) < 0.0) edge.normal = -edge.normal;
                mBoundaryEdges[face].push_back(edge);
            }
        }
    }
    for (const int v : mScene.cornerVertices) mReport.sceneTips.push_back(mSceneDisk[v]);
    for (const int v : mDisplay.cornerVertices) mReport.displayTips.push_back(mDisplayDisk[v]);
    for (std::size_t k = 0; k < mReport.sceneTips.size(); ++k) {
        const double degrees = std::abs(std::arg(mReport.sceneTips[k] / mReport.displayTips[k])) * 180.0 / std::numbers::pi;
        mReport.tipMismatchDegrees = std::max(mReport.tipMismatchDegrees, degrees);
    }
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

bool ConformalMap::sceneFromVisible(const glm::dvec3& display, glm::dvec3& scene) const {
    const MeshLocation location = locateDirection(mDisplay, display);
    if (location.triangle < 0) return false;
    scene = sceneFromDisk(displayDiskAt(location, display));
    return true;
}

glm::dvec3 ConformalMap::sceneFromDisplay(const glm::dvec3& display) const {
    const glm::dvec3 d = unitDirection(display, "display");
    glm::dvec3 scene;
    return sceneFromVisible(d, scene) ? scene : missingExtension(d);
}

glm::dvec3 ConformalMap::displayFromScene(const glm::dvec3& scene) const {
    return displayFromDisk(diskFromScene(scene));
}

glm::dvec3 ConformalMap::missingExtension(const glm::dvec3& display) const {
    // Point reflection through the foot on the nearest edge of the direction's missing face:
    // F(b + v) := 2 F(b) - F(b - v) continues F with its value and normal derivative across the
    // edge. Only texels near the edges matter (filtering across them); deeper in, where the
    // foot or the mirrored direction falls outside the display domain, the value at the foot
    // or at the edge's nearer corner is held. The edge is the nearest of the direction's own
    // missing face, or of any missing face where rounding left a direction on an edge outside
    // both the mesh and every missing face's closed rectangle.
    const int face = missingFaceOfDirection(mSettings.box, display);
    const BoundaryEdge* nearest = nullptr;
    for (int f = 0; f < kBoxFaceCount; ++f) {
        if (face >= 0 && f != face) continue;
        for (const BoundaryEdge& edge : mBoundaryEdges[f]) {
            if (!nearest || std::abs(glm::dot(display, edge.normal)) < std::abs(glm::dot(display, nearest->normal))) {
                nearest = &edge;
            }
        }
    }
    if (!nearest) return display;  // no edge at all: validateCaveBox refuses such a box
    const glm::dvec3& normal = nearest->normal;
    const double height = glm::dot(display, normal);
    const glm::dvec3 mirrored = display - 2.0 * height * normal;
    constexpr double kInset = 1e-9;  // moves the foot off the edge into the display domain
    glm::dvec3 onEdge;
    if (!sceneFromVisible(glm::normalize(display - (height + kInset) * normal), onEdge)) {
        const glm::dvec3& corner =
            glm::dot(display, nearest->from) > glm::dot(display, nearest->to) ? nearest->from : nearest->to;
        if (!sceneFromVisible(corner, onEdge)) return display;
        return onEdge;
    }
    glm::dvec3 across;
    if (!sceneFromVisible(mirrored, across)) return onEdge;
    const glm::dvec3 extended = 2.0 * onEdge - across;
    const double length = glm::length(extended);
    return length > 1e-12 ? extended / length : onEdge;
}

}  // namespace conformal
