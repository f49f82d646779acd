/// @brief The conformal map F = phi6^-1 o phi5 between display and scene directions, from
/// Ricci-flow Riemann maps of Omega5 and Omega6 aligned by Möbius transformations.
#pragma once

#include <complex>
#include <vector>

#include "conformal/cave_box.h"
#include "conformal/direction_map.h"
#include "conformal/disk_locator.h"
#include "conformal/holomorphic_interpolation.h"
#include "conformal/riemann_map.h"
#include "conformal/sphere_mesh.h"

namespace conformal {

/// How the maps are evaluated between mesh vertices.
enum class MeshInterpolation {
    Barycentric,            ///< piecewise linear on the chord triangles
    HolomorphicQuadratic,   ///< blended local holomorphic quadratics (see holomorphic_interpolation.h)
};

struct ConformalMapSettings {
    CaveBox box;
    SphereMeshSettings mesh;
    RicciFlowSettings flow;
    MeshInterpolation interpolation = MeshInterpolation::HolomorphicQuadratic;
    /// Also flow the half-resolution meshes and extrapolate the vertex values (Richardson),
    /// which cancels the flow's O(h^2) discretisation error; costs about a quarter more.
    bool isExtrapolated = true;
};

/// What building the map measured.
struct ConformalMapReport {
    RiemannMapReport scene;      ///< phi6's construction
    RiemannMapReport display;    ///< phi5's construction
    /// phi6 and phi5 images of the slit's tips (order of SphereMesh::cornerVertices). The
    /// alignment fixes two of them; where the others differ between the two disks, F does not
    /// send that reflex corner exactly onto its tip. For the cabin corner k goes to i^k.
    std::vector<std::complex<double>> sceneTips;
    std::vector<std::complex<double>> displayTips;
    double tipMismatchDegrees = 0.0;           ///< largest angle between a tip's two images
    int alignmentSector = -1;                  ///< the sector whose tips and middle are aligned
    std::complex<double> sceneNadir{0.0};      ///< phi6 image of the floor centre
    std::complex<double> displayNadir{0.0};    ///< phi5 image of the floor centre
    double seconds = 0.0;                      ///< wall-clock time to build
    /// Whether Richardson extrapolation was applied; false where it was not asked for or where
    /// it folded triangles over (strongly graded meshes), and the plain flow's map was kept.
    bool isSceneExtrapolated = true;
    bool isDisplayExtrapolated = true;
};

class ConformalMap final : public DirectionMap {
public:
    /// Builds both meshes and runs both flows (in parallel). Throws on failure.
    explicit ConformalMap(const ConformalMapSettings& settings);
    // The interpolants point into the meshes: the map stays where it was built.
    ConformalMap(const ConformalMap&) = delete;
    ConformalMap& operator=(const ConformalMap&) = delete;

    /// F and G take a direction at any finite, non-zero length; a zero or non-finite vector
    /// throws std::invalid_argument (so do the two disk maps below).
    glm::dvec3 sceneFromDisplay(const glm::dvec3& display) const override;
    glm::dvec3 displayFromScene(const glm::dvec3& scene) const override;

    /// phi5 of a display direction in Omega5 (throws std::domain_error for ceiling directions).
    std::complex<double> diskFromDisplay(const glm::dvec3& display) const;
    /// phi6 of a scene direction.
    std::complex<double> diskFromScene(const glm::dvec3& scene) const;
    /// phi6^-1 and phi5^-1 of a point of the closed unit disk.
    glm::dvec3 sceneFromDisk(std::complex<double> zeta) const;
    glm::dvec3 displayFromDisk(std::complex<double> zeta) const;

    const SphereMesh& sceneMesh() const { return mScene; }
    const SphereMesh& displayMesh() const { return mDisplay; }
    /// Aligned disk positions per vertex of sceneMesh() / displayMesh().
    const std::vector<std::complex<double>>& sceneDisk() const { return mSceneDisk; }
    const std::vector<std::complex<double>>& displayDisk() const { return mDisplayDisk; }
    const ConformalMapReport& report() const { return mReport; }
    const ConformalMapSettings& settings() const { return mSettings; }

private:
    /// One edge between a missing face and a present one: the plane through it and the map
    /// centre (normal toward the missing side) and the directions of its two corners.
    struct BoundaryEdge {
        glm::dvec3 normal{0.0};
        glm::dvec3 from{0.0};
        glm::dvec3 to{0.0};
    };

    glm::dvec3 missingExtension(const glm::dvec3& display) const;
    /// F at a direction of the closed display domain; false outside it.
    bool sceneFromVisible(const glm::dvec3& display, glm::dvec3& scene) const;
    std::complex<double> displayDiskAt(const MeshLocation& location, const glm::dvec3& display) const;

    ConformalMapSettings mSettings;
    SphereMesh mScene;
    SphereMesh mDisplay;
    std::vector<std::complex<double>> mSceneDisk;
    std::vector<std::complex<double>> mDisplayDisk;
    DiskLocator mSceneLocator;
    DiskLocator mDisplayLocator;
    SphereToPlaneInterpolant mSceneForward;     ///< phi6
    SphereToPlaneInterpolant mDisplayForward;   ///< phi5
    PlaneToSphereInterpolant mSceneInverse;     ///< phi6^-1
    PlaneToSphereInterpolant mDisplayInverse;   ///< phi5^-1
    bool mIsSmooth = true;
    std::array<std::vector<BoundaryEdge>, kBoxFaceCount> mBoundaryEdges;  ///< per missing face
    ConformalMapReport mReport;
};

}  // namespace conformal
