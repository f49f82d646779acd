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
    Scene,    ///< Omega6: the whole sphere cut open along the slit tree X inside the missing
              ///< walls (see buildSphereMesh); its boundary is the slit's sides.
    Display,  ///< Omega5: the sphere minus the closed missing walls' directions.
};

/// A straight run of the slit on the box's lattice: from + k step for k = 0..steps.
struct SlitSegment {
    std::array<int, 3> from{};
    std::array<int, 3> step{};
    int steps = 0;
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
    /// Vertices at the slit's tips (order of slitTipCorners): the tips of Omega6's slit, the
    /// reflex corners of Omega5. For the cabin the four ceiling corners, in the order of
    /// ceilingCornerDirections.
    std::vector<int> cornerVertices;
    /// The vertex at the floor's centre (the nadir when the map centre is centred in x and z);
    /// without a floor, the centre of the first present face among front, right, left, back,
    /// ceiling.
    int nadirVertex = -1;
    /// The missing walls less the slit fall into sectors, one per pair of tips that follow each
    /// other along the boundary; sector k runs from tip sectorTips[k][0] to tip sectorTips[k][1]
    /// (indices into cornerVertices), and where those follow each other in azimuth order the
    /// first is tip k. For the cabin sector k is the ceiling triangle (zenith, corner k,
    /// corner k + 1).
    std::vector<std::array<int, 2>> sectorTips;
    /// For Omega6, the sector that owns each copy of a vertex on the slit; -1 for every other
    /// vertex.
    std::vector<int> slitSector;
    /// The sector whose closure holds each vertex: slit copies their own, vertices inside the
    /// missing walls or on their boundary (Omega5's boundary) the sector around them; -1 for the
    /// tips and every vertex of the present walls' interior.
    std::vector<int> missingSector;
    /// The slit X as lattice runs: each missing face of the slit's tree contributes the
    /// half-diagonals from its centre to its tip corners, each tree edge two runs from one face's
    /// centre to the shared edge's midpoint and on to the other's.
    std::vector<SlitSegment> slit;
    /// Per vertex, its grid-line indices (ix, iy, iz) on the box's lattice.
    std::vector<std::array<int, 3>> lattice;
    /// Grid lines along x, y, z in CAVE-space metres (box centred at the origin).
    std::array<std::vector<double>, 3> gridLines;
    /// Per face (Vulkan order +X, -X, +Y, -Y, +Z, -Z), two triangle indices per grid cell, or -1
    /// where the face is not meshed (the ceiling of Omega5).
    std::array<std::vector<int>, 6> cellTriangles;
};

/// Builds the mesh of `domain` for `box`. The slit X follows a fixed rule: the missing faces'
/// tree (breadth first over shared edges from the lowest-numbered missing face, pruned of
/// leaves that hold no tip), each face's half-diagonals to its tip corners, and between faces
/// of the tree the lines through their centres and the shared edge's midpoint. For the cabin it
/// is the cross of the ceiling's diagonals; for the classic CAVE (ceiling and back missing) an
/// H: the medial axis of the two faces unfolded into one rectangle. Faces that carry slit
/// diagonals get one segment count on both of their axes, so the diagonals are mesh edges.
/// Throws std::invalid_argument on bad settings or a box validateCaveBox refuses.
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
