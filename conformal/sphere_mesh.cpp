/// @brief Sphere meshes from the box's faces: a tensor grid per face, each cell split along the
/// diagonal that points toward the face's centre (so the ceiling's diagonals are mesh edges),
/// projected to unit directions, and cut along the slit X for Omega6.
#include "conformal/sphere_mesh.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include <glm/geometric.hpp>

namespace conformal {

namespace {

constexpr int kCeilingFace = 2;  // +Y in Vulkan face order

/// Multiples of 4, so that the mesh and its half-resolution companion both have even counts
/// (a vertex at each face's centre).
int segmentCount(double fraction, int resolution, int coarsening) {
    const int quarter = std::max(1, static_cast<int>(std::lround(fraction * resolution / 4.0)));
    return 4 * quarter / coarsening;
}

/// Grid lines on [-extent/2, extent/2], graded toward both ends with exponent p.
std::vector<double> gradedGridLines(double extent, int segments, double grading) {
    std::vector<double> lines(segments + 1);
    for (int i = 0; i <= segments; ++i) {
        const double t = static_cast<double>(i) / segments;
        const double a = std::pow(t, grading);
        const double b = std::pow(1.0 - t, grading);
        lines[i] = extent * (a / (a + b) - 0.5);
    }
    lines.front() = -0.5 * extent;
    lines.back() = 0.5 * extent;
    lines[segments / 2] = 0.0;  // exact, so the diagonals meet the face centre exactly
    return lines;
}

}  // namespace

int ceilingSectorOf(double x, double z) {
    if (z >= std::abs(x)) return 0;
    if (x <= -std::abs(z)) return 1;
    if (z <= -std::abs(x)) return 2;
    return 3;
}

glm::dvec3 chordBarycentric(const glm::dvec3& direction, const glm::dvec3& a, const glm::dvec3& b,
                            const glm::dvec3& c) {
    // The ray t * direction meets the plane of (a, b, c) where the volumes
    // det(direction, b, c) : det(a, direction, c) : det(a, b, direction) give the weights.
    const glm::dvec3 weights(glm::dot(direction, glm::cross(b, c)),
                             glm::dot(direction, glm::cross(c, a)),
                             glm::dot(direction, glm::cross(a, b)));
    const double sum = weights.x + weights.y + weights.z;
    return weights / sum;
}

SphereMesh buildSphereMesh(const CaveBox& box, SphereDomain domain,
                           const SphereMeshSettings& settings) {
    validateCaveBox(box);
    if (settings.resolution < 2 || settings.resolution > 8192) {
        throw std::invalid_argument("sphere mesh: resolution " +
                                    std::to_string(settings.resolution) +
                                    " is outside [2, 8192]");
    }
    if (settings.coarsening != 1 && settings.coarsening != 2) {
        throw std::invalid_argument("sphere mesh: coarsening " + std::to_string(settings.coarsening) +
                                    " is not 1 or 2");
    }
    if (!(settings.grading >= 1.0 && settings.grading <= 8.0)) {
        throw std::invalid_argument("sphere mesh: grading " + std::to_string(settings.grading) +
                                    " is outside [1, 8]");
    }

    SphereMesh sphere;
    sphere.domain = domain;
    sphere.box = box;
    const double longest = std::max({box.size.x, box.size.y, box.size.z});
    // x and z share one segment count and one normalised grading, so that the ceiling's grid
    // has its diagonals' points as vertices even when the ceiling is not square.
    const int horizontalSegments = segmentCount(std::max(box.size.x, box.size.z) / longest,
                                                settings.resolution, settings.coarsening);
    const int verticalSegments =
        segmentCount(box.size.y / longest, settings.resolution, settings.coarsening);
    sphere.gridLines[0] = gradedGridLines(box.size.x, horizontalSegments, settings.grading);
    sphere.gridLines[1] = gradedGridLines(box.size.y, verticalSegments, settings.grading);
    sphere.gridLines[2] = gradedGridLines(box.size.z, horizontalSegments, settings.grading);
    const std::array<int, 3> lineCount = {horizontalSegments + 1, verticalSegments + 1,
                                          horizontalSegments + 1};

    // Vertices are keyed by their lattice index (ix, iy, iz) and, for slit copies, the sector.
    std::unordered_map<std::uint64_t, int> vertexOfKey;
    auto vertexAt = [&](const std::array<int, 3>& lattice, int sector) {
        const std::uint64_t latticeKey =
            static_cast<std::uint64_t>(lattice[0]) +
            static_cast<std::uint64_t>(lineCount[0]) *
                (static_cast<std::uint64_t>(lattice[1]) +
                 static_cast<std::uint64_t>(lineCount[1]) * static_cast<std::uint64_t>(lattice[2]));
        const std::uint64_t key = latticeKey * 5 + static_cast<std::uint64_t>(sector + 1);
        const auto [it, isNew] =
            vertexOfKey.emplace(key, static_cast<int>(sphere.mesh.positions.size()));
        if (isNew) {
            const glm::dvec3 point(sphere.gridLines[0][lattice[0]], sphere.gridLines[1][lattice[1]],
                                   sphere.gridLines[2][lattice[2]]);
            sphere.mesh.positions.push_back(glm::normalize(point - box.mapCentre));
            sphere.slitSector.push_back(sector);
            sphere.lattice.push_back(lattice);
        }
        return it->second;
    };

    const int half = horizontalSegments / 2;
    for (int face = 0; face < 6; ++face) {
        const int normalAxis = face / 2;
        const bool isPositive = face % 2 == 0;
        const int axisA = (normalAxis + 1) % 3;
        const int axisB = (normalAxis + 2) % 3;
        const int cellsA = lineCount[axisA] - 1;
        const int cellsB = lineCount[axisB] - 1;
        auto& cells = sphere.cellTriangles[face];
        cells.assign(static_cast<std::size_t>(2) * cellsA * cellsB, -1);
        const bool isCeiling = face == kCeilingFace;
        if (isCeiling && domain == SphereDomain::Display) continue;

        for (int ia = 0; ia < cellsA; ++ia) {
            for (int ib = 0; ib < cellsB; ++ib) {
                auto lattice = [&](int da, int db) {
                    std::array<int, 3> index{};
                    index[normalAxis] = isPositive ? lineCount[normalAxis] - 1 : 0;
                    index[axisA] = ia + da;
                    index[axisB] = ib + db;
                    return index;
                };
                // Split along the diagonal that points toward the face's centre: the
                // pattern keeps the box's symmetries and puts the ceiling's diagonals on edges.
                const bool isMainDiagonal = (2 * ia < cellsA) == (2 * ib < cellsB);
                std::array<std::array<std::array<int, 2>, 3>, 2> halves{};
                if (isMainDiagonal) {
                    halves[0] = {{{0, 0}, {1, 0}, {1, 1}}};
                    halves[1] = {{{0, 0}, {1, 1}, {0, 1}}};
                } else {
                    halves[0] = {{{0, 0}, {1, 0}, {0, 1}}};
                    halves[1] = {{{1, 0}, {1, 1}, {0, 1}}};
                }
                for (int h = 0; h < 2; ++h) {
                    int sector = -1;
                    if (isCeiling) {
                        // Ceiling grid: axisA is z, axisB is x.
                        double sumA = 0.0;
                        double sumB = 0.0;
                        for (const auto& corner : halves[h]) {
                            sumA += ia + corner[0] - half;
                            sumB += ib + corner[1] - half;
                        }
                        sector = ceilingSectorOf(sumB, sumA);
                    }
                    std::array<int, 3> triangle{};
                    for (int c = 0; c < 3; ++c) {
                        const auto index = lattice(halves[h][c][0], halves[h][c][1]);
                        int copySector = -1;
                        if (isCeiling) {
                            const int dx = index[0] - half;
                            const int dz = index[2] - half;
                            const bool isOnDiagonal = std::abs(dx) == std::abs(dz);
                            const bool isCorner = std::abs(dx) == half;
                            if (isOnDiagonal && !isCorner) copySector = sector;
                        }
                        triangle[c] = vertexAt(index, copySector);
                    }
                    // Orient counter-clockwise seen from outside.
                    const auto& p = sphere.mesh.positions;
                    const glm::dvec3 normal = glm::cross(p[triangle[1]] - p[triangle[0]],
                                                         p[triangle[2]] - p[triangle[0]]);
                    if (glm::dot(normal, p[triangle[0]] + p[triangle[1]] + p[triangle[2]]) < 0.0) {
                        std::swap(triangle[1], triangle[2]);
                    }
                    cells[2 * (static_cast<std::size_t>(ia) * cellsB + ib) + h] =
                        static_cast<int>(sphere.mesh.triangles.size());
                    sphere.mesh.triangles.push_back(triangle);
                }
            }
        }
    }

    const int top = lineCount[1] - 1;
    const int last = horizontalSegments;
    const std::array<std::array<int, 3>, 4> cornerLattice = {
        {{last, top, last}, {0, top, last}, {0, top, 0}, {last, top, 0}}};
    for (int k = 0; k < 4; ++k) sphere.cornerVertices[k] = vertexAt(cornerLattice[k], -1);
    sphere.nadirVertex = vertexAt({half, 0, half}, -1);
    return sphere;
}

MeshLocation locateDirection(const SphereMesh& sphere, const glm::dvec3& direction) {
    const glm::dvec3 halfSize = 0.5 * sphere.box.size;
    const glm::dvec3& centre = sphere.box.mapCentre;
    // The face the ray leaves through: the smallest positive exit distance.
    int normalAxis = 0;
    double exit = std::numeric_limits<double>::infinity();
    for (int axis = 0; axis < 3; ++axis) {
        if (direction[axis] == 0.0) continue;
        const double bound = direction[axis] > 0.0 ? halfSize[axis] : -halfSize[axis];
        const double t = (bound - centre[axis]) / direction[axis];
        if (t < exit) {
            exit = t;
            normalAxis = axis;
        }
    }
    MeshLocation location;
    if (!std::isfinite(exit)) return location;
    const int face = 2 * normalAxis + (direction[normalAxis] > 0.0 ? 0 : 1);
    const glm::dvec3 hit = centre + exit * direction;
    const int axisA = (normalAxis + 1) % 3;
    const int axisB = (normalAxis + 2) % 3;

    auto cellOf = [&](int axis, double& fraction) {
        const auto& lines = sphere.gridLines[axis];
        const auto upper = std::upper_bound(lines.begin(), lines.end(), hit[axis]);
        int cell = static_cast<int>(upper - lines.begin()) - 1;
        cell = std::clamp(cell, 0, static_cast<int>(lines.size()) - 2);
        fraction = (hit[axis] - lines[cell]) / (lines[cell + 1] - lines[cell]);
        return cell;
    };
    double fa = 0.0;
    double fb = 0.0;
    const int ia = cellOf(axisA, fa);
    const int ib = cellOf(axisB, fb);
    const int cellsA = static_cast<int>(sphere.gridLines[axisA].size()) - 1;
    const int cellsB = static_cast<int>(sphere.gridLines[axisB].size()) - 1;
    const bool isMainDiagonal = (2 * ia < cellsA) == (2 * ib < cellsB);
    const int halfIndex = isMainDiagonal ? (fb <= fa ? 0 : 1) : (fa + fb <= 1.0 ? 0 : 1);
    location.triangle =
        sphere.cellTriangles[face][2 * (static_cast<std::size_t>(ia) * cellsB + ib) + halfIndex];
    if (location.triangle < 0) return location;
    const auto& tri = sphere.mesh.triangles[location.triangle];
    const auto& p = sphere.mesh.positions;
    location.barycentric = chordBarycentric(direction, p[tri[0]], p[tri[1]], p[tri[2]]);
    return location;
}

}  // namespace conformal
