/// @brief Meshes of the sphere of directions cut to the scene domain Omega6 or the display
/// domain Omega5, built from subdivided box faces, with O(log n) point location.
#pragma once

#include <array>
#include <vector>

#include <glm/vec3.hpp>

#include "conformal/cave_box.h"
#include "conformal/triangle_mesh.h"

namespace conformal {

/// Which part of the sphere of directions a mesh covers.
enum class SphereDomain {
    Scene,    ///< Omega6: the whole sphere cut open along the cross slit X (the ceiling's
              ///< diagonals seen from the map centre); its boundary is the slit's two sides.
    Display,  ///< Omega5: the sphere minus the closed spherical square of ceiling directions.
};

struct SphereMeshSettings {
    /// Grid segments along the longest box edge; the others get proportionally many (counts
    /// rounded to multiples of 4, at least 4). Vertices: about 6 resolution^2 for a cube.
    int resolution = 112;
    /// Grading exponent p >= 1 of the grid lines toward the box edges and hence the corners,
    /// where the maps are singular: t -> t^p / (t^p + (1 - t)^p). 1 is a uniform grid.
    double grading = 1.75;
    /// 1 for the mesh itself; 2 for its coarse companion with every other grid line (the
    /// same lines, so its vertices are a subset), used for Richardson extrapolation.
    int coarsening = 1;
};

/// A mesh of unit directions (CAVE space, seen from the box's map centre), triangles
/// counter-clockwise seen from outside, plus what point location needs.
struct SphereMesh {
    TriangleMesh mesh;
    SphereDomain domain = SphereDomain::Scene;
    CaveBox box;
    /// Vertices at the four ceiling corners (order of ceilingCornerDirections): the slit tips of
    /// Omega6, the reflex corners of Omega5.
    std::array<int, 4> cornerVertices{};
    /// The vertex at the floor's centre (the nadir when the map centre is centred in x and z).
    int nadirVertex = -1;
    /// For Omega6, the ceiling sector k (triangle zenith, corner k, corner k + 1) that owns each
    /// copy of a vertex on the slit; -1 for every other vertex.
    std::vector<int> slitSector;
    /// Per vertex, its grid-line indices (ix, iy, iz) on the box's lattice.
    std::vector<std::array<int, 3>> lattice;
    /// Grid lines along x, y, z in CAVE-space metres (box centred at the origin).
    std::array<std::vector<double>, 3> gridLines;
    /// Per face (Vulkan order +X, -X, +Y, -Y, +Z, -Z), two triangle indices per grid cell, or -1
    /// where the face is not meshed (the ceiling of Omega5).
    std::array<std::vector<int>, 6> cellTriangles;
};

/// The ceiling sector of a ceiling point with x, z in units of the half width and half depth:
/// k such that the point lies in the triangle (zenith, corner k, corner k + 1).
int ceilingSectorOf(double x, double z);

/// Builds the mesh of `domain` for `box`. Throws std::invalid_argument on bad settings.
SphereMesh buildSphereMesh(const CaveBox& box, SphereDomain domain,
                           const SphereMeshSettings& settings);

/// A point on a mesh: the triangle holding it and barycentric coordinates on that chord
/// triangle (the ray from the centre meets the triangle's plane there).
struct MeshLocation {
    int triangle = -1;  ///< -1 when the direction lies outside the mesh's domain
    glm::dvec3 barycentric{0.0};
};

/// Locates a unit direction by the box face and grid cell its ray from the map centre crosses
/// (binary search on the grid lines). Directions on the Omega6 slit go to either side.
MeshLocation locateDirection(const SphereMesh& sphere, const glm::dvec3& direction);

/// Barycentric coordinates of the point where the ray along `direction` meets the plane of the
/// chord triangle (a, b, c) of unit vectors; they sum to 1.
glm::dvec3 chordBarycentric(const glm::dvec3& direction, const glm::dvec3& a, const glm::dvec3& b,
                            const glm::dvec3& c);

}  // namespace conformal
