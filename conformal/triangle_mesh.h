/// @brief A plain triangle mesh (vertex positions, triangles) and its half-edge adjacency.
#pragma once

#include <array>
#include <vector>

#include <glm/vec3.hpp>

namespace conformal {

/// Positions (#V, any frame) and triangles (#F by 3 vertex indices), counter-clockwise seen
/// from outside the sphere for the meshes of this module.
struct TriangleMesh {
    std::vector<glm::dvec3> positions;
    std::vector<std::array<int, 3>> triangles;
};

/// Half-edge h = 3 t + e runs from corner e to corner (e + 1) % 3 of triangle t.
/// Returns, for each half-edge, its twin running the other way, or -1 on the boundary.
/// Throws std::runtime_error when an edge is used twice in the same direction (a non-manifold
/// or inconsistently oriented mesh).
std::vector<int> twinHalfEdges(const TriangleMesh& mesh);

/// True for every vertex that ends a boundary half-edge.
std::vector<char> boundaryVertexFlags(const TriangleMesh& mesh, const std::vector<int>& twins);

}  // namespace conformal
