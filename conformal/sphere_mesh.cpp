/// @brief Sphere meshes from the box's faces: a tensor grid per face, each cell split along the
/// diagonal that points toward the face's centre (so the ceiling's diagonals are mesh edges),
/// projected to unit directions, and cut along the slit X for Omega6.
#include "conformal/sphere_mesh.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include <glm/geometric.hpp>

namespace conformal {

namespace {

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

using Lattice = std::array<int, 3>;

/// The box's lattice: grid-line counts per axis and the indices of faces, centres and corners.
struct BoxLattice {
    std::array<int, 3> lineCount{};

    int last(int axis) const { return lineCount[axis] - 1; }
    int middle(int axis) const { return last(axis) / 2; }
    std::uint64_t key(const Lattice& l) const {
        return static_cast<std::uint64_t>(l[0]) +
               static_cast<std::uint64_t>(lineCount[0]) *
                   (static_cast<std::uint64_t>(l[1]) +
                    static_cast<std::uint64_t>(lineCount[1]) * static_cast<std::uint64_t>(l[2]));
    }
    int plane(int face) const { return face % 2 == 0 ? last(face / 2) : 0; }
    Lattice faceCentre(int face) const {
        Lattice l = {middle(0), middle(1), middle(2)};
        l[face / 2] = plane(face);
        return l;
    }
    Lattice corner(int corner) const {
        Lattice l{};
        for (int axis = 0; axis < 3; ++axis) l[axis] = ((corner >> axis) & 1) != 0 ? last(axis) : 0;
        return l;
    }
};

int signOf(int v) { return (v > 0) - (v < 0); }

/// The slit's tree of missing faces: breadth first over shared edges from the lowest-numbered
/// missing face, then leaves without a tip pruned (they would end the slit inside the missing
/// walls). Returns the tree's faces (bit set) and edges.
std::pair<std::uint32_t, std::vector<std::array<int, 2>>> slitFaceTree(const CaveBox& box) {
    std::vector<int> faces;
    for (int f = 0; f < kBoxFaceCount; ++f) {
        if (isFaceMissing(box, f)) faces.push_back(f);
    }
    std::uint32_t inTree = faceBit(faces.front());
    std::vector<std::array<int, 2>> edges;
    std::vector<int> queue = {faces.front()};
    for (std::size_t q = 0; q < queue.size(); ++q) {
        for (const int g : faces) {
            if ((inTree & faceBit(g)) != 0 || queue[q] / 2 == g / 2) continue;
            inTree |= faceBit(g);
            edges.push_back({queue[q], g});
            queue.push_back(g);
        }
    }
    auto hasTip = [&](int face) {
        for (int c = 0; c < 8; ++c) {
            const auto at = facesAtCorner(c);
            if (std::find(at.begin(), at.end(), face) != at.end() && missingFacesAtCorner(box, c) == 1) return true;
        }
        return false;
    };
    for (bool isPruning = true; isPruning;) {
        isPruning = false;
        for (const int f : faces) {
            if ((inTree & faceBit(f)) == 0 || hasTip(f)) continue;
            const auto degree = std::count_if(edges.begin(), edges.end(), [f](const auto& e) { return e[0] == f || e[1] == f; });
            if (degree != 1) continue;
            edges.erase(std::remove_if(edges.begin(), edges.end(), [f](const auto& e) { return e[0] == f || e[1] == f; }),
                        edges.end());
            inTree &= ~faceBit(f);
            isPruning = true;
        }
    }
    return {inTree, edges};
}

/// The slit X on the lattice (see buildSphereMesh).
std::vector<SlitSegment> slitSegments(const CaveBox& box, const BoxLattice& lattice) {
    const auto [treeFaces, treeEdges] = slitFaceTree(box);
    std::vector<SlitSegment> slit;
    auto addRun = [&](const Lattice& from, const Lattice& to) {
        SlitSegment run;
        run.from = from;
        int steps = 0;
        for (int axis = 0; axis < 3; ++axis) {
            run.step[axis] = signOf(to[axis] - from[axis]);
            const int length = std::abs(to[axis] - from[axis]);
            if (length == 0) continue;
            if (steps != 0 && steps != length) throw std::logic_error("sphere mesh: a slit run is not a lattice diagonal");
            steps = length;
        }
        run.steps = steps;
        slit.push_back(run);
    };
    for (int face = 0; face < kBoxFaceCount; ++face) {
        if ((treeFaces & faceBit(face)) == 0) continue;
        for (int c = 0; c < 8; ++c) {
            const auto at = facesAtCorner(c);
            if (std::find(at.begin(), at.end(), face) == at.end() || missingFacesAtCorner(box, c) != 1) continue;
            addRun(lattice.faceCentre(face), lattice.corner(c));
        }
    }
    for (const auto& [f, g] : treeEdges) {
        Lattice midpoint = {lattice.middle(0), lattice.middle(1), lattice.middle(2)};
        midpoint[f / 2] = lattice.plane(f);
        midpoint[g / 2] = lattice.plane(g);
        addRun(lattice.faceCentre(f), midpoint);
        addRun(lattice.faceCentre(g), midpoint);
    }
    return slit;
}

/// Union-find over triangle indices.
int rootOf(std::vector<int>& parent, int i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
}

}  // namespace

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
    const double longest = std::max({box.size.x, box.size.z, box.size.y});
    // x and z share one segment count and one normalised grading, so that the ceiling's grid
    // has its diagonals' points as vertices even when the ceiling is not square. A missing wall
    // (x or z normal) needs the same of y.
    bool isWallMissing = false;
    for (const int face : {0, 1, 4, 5}) isWallMissing = isWallMissing || isFaceMissing(box, face);
    const int horizontalSegments = segmentCount(
        (isWallMissing ? longest : std::max(box.size.x, box.size.z)) / longest, settings.resolution, settings.coarsening);
    const int verticalSegments =
        isWallMissing ? horizontalSegments : segmentCount(box.size.y / longest, settings.resolution, settings.coarsening);
    sphere.gridLines[0] = gradedGridLines(box.size.x, horizontalSegments, settings.grading);
    sphere.gridLines[1] = gradedGridLines(box.size.y, verticalSegments, settings.grading);
    sphere.gridLines[2] = gradedGridLines(box.size.z, horizontalSegments, settings.grading);
    BoxLattice lattice;
    lattice.lineCount = {horizontalSegments + 1, verticalSegments + 1, horizontalSegments + 1};

    // The slit: which lattice points lie on it, and where along which run.
    sphere.slit = slitSegments(box, lattice);
    std::unordered_map<std::uint64_t, std::vector<std::array<int, 2>>> slitRunsAt;
    for (int s = 0; s < static_cast<int>(sphere.slit.size()); ++s) {
        const SlitSegment& run = sphere.slit[s];
        for (int k = 0; k <= run.steps; ++k) {
            const Lattice at = {run.from[0] + k * run.step[0], run.from[1] + k * run.step[1], run.from[2] + k * run.step[2]};
            slitRunsAt[lattice.key(at)].push_back({s, k});
        }
    }
    const std::vector<int> tipCorners = slitTipCorners(box);
    std::unordered_map<std::uint64_t, int> tipOfKey;
    for (int t = 0; t < static_cast<int>(tipCorners.size()); ++t) tipOfKey[lattice.key(lattice.corner(tipCorners[t]))] = t;
    auto isSlitEdge = [&](std::uint64_t a, std::uint64_t b) {
        const auto ia = slitRunsAt.find(a);
        const auto ib = slitRunsAt.find(b);
        if (ia == slitRunsAt.end() || ib == slitRunsAt.end()) return false;
        for (const auto& [runA, kA] : ia->second) {
            for (const auto& [runB, kB] : ib->second) {
                if (runA == runB && std::abs(kA - kB) == 1) return true;
            }
        }
        return false;
    };

    // Pass 1: every face's triangles on the lattice. Each cell is split along the diagonal that
    // points toward the face's centre: the pattern keeps the box's symmetries and puts every
    // face's diagonals on edges.
    struct LatticeTriangle {
        int face = 0;
        int cell = 0;  ///< index into cellTriangles[face]
        std::array<Lattice, 3> corners{};
    };
    std::vector<LatticeTriangle> triangles;
    for (int face = 0; face < kBoxFaceCount; ++face) {
        const int normalAxis = face / 2;
        const int axisA = (normalAxis + 1) % 3;
        const int axisB = (normalAxis + 2) % 3;
        const int cellsA = lattice.lineCount[axisA] - 1;
        const int cellsB = lattice.lineCount[axisB] - 1;
        sphere.cellTriangles[face].assign(static_cast<std::size_t>(2) * cellsA * cellsB, -1);
        for (int ia = 0; ia < cellsA; ++ia) {
            for (int ib = 0; ib < cellsB; ++ib) {
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
                    LatticeTriangle triangle;
                    triangle.face = face;
                    triangle.cell = 2 * (ia * cellsB + ib) + h;
                    for (int c = 0; c < 3; ++c) {
                        Lattice& index = triangle.corners[c];
                        index[normalAxis] = lattice.plane(face);
                        index[axisA] = ia + halves[h][c][0];
                        index[axisB] = ib + halves[h][c][1];
                    }
                    triangles.push_back(triangle);
                }
            }
        }
    }

    // The missing walls' triangles fall into sectors: connected across edges off the slit.
    const int triangleCount = static_cast<int>(triangles.size());
    std::vector<int> parent(triangleCount);
    for (int t = 0; t < triangleCount; ++t) parent[t] = t;
    std::unordered_map<std::uint64_t, int> triangleOfEdge;
    const std::uint64_t keyCount = lattice.key({lattice.last(0), lattice.last(1), lattice.last(2)}) + 1;
    for (int t = 0; t < triangleCount; ++t) {
        if (!isFaceMissing(box, triangles[t].face)) continue;
        for (int c = 0; c < 3; ++c) {
            const std::uint64_t a = lattice.key(triangles[t].corners[c]);
            const std::uint64_t b = lattice.key(triangles[t].corners[(c + 1) % 3]);
            if (isSlitEdge(a, b)) continue;
            const auto [it, isNew] = triangleOfEdge.emplace(std::min(a, b) * keyCount + std::max(a, b), t);
            if (!isNew) parent[rootOf(parent, t)] = rootOf(parent, it->second);
        }
    }
    // Number the sectors by their tips: sector k runs from tip k to the next tip.
    std::unordered_map<int, std::vector<int>> tipsOfRoot;
    for (int t = 0; t < triangleCount; ++t) {
        if (!isFaceMissing(box, triangles[t].face)) continue;
        auto& tips = tipsOfRoot[rootOf(parent, t)];
        for (const Lattice& corner : triangles[t].corners) {
            const auto tip = tipOfKey.find(lattice.key(corner));
            if (tip != tipOfKey.end() && std::find(tips.begin(), tips.end(), tip->second) == tips.end()) {
                tips.push_back(tip->second);
            }
        }
    }
    const int tipCount = static_cast<int>(tipCorners.size());
    std::vector<std::pair<int, int>> orderedRoots;  // (key, root)
    for (auto& [root, tips] : tipsOfRoot) {
        if (tips.size() != 2) {
            throw std::logic_error("sphere mesh: a sector of the missing walls touches " + std::to_string(tips.size()) +
                                   " slit tips instead of 2");
        }
        std::sort(tips.begin(), tips.end());
        // The sector runs from the tip whose successor in azimuth is the other; tips that are
        // not neighbours in azimuth order after all the others.
        int from = tipCount + tips[0] * tipCount + tips[1];
        if ((tips[0] + 1) % tipCount == tips[1]) {
            from = tips[0];
        } else if ((tips[1] + 1) % tipCount == tips[0]) {
            from = tips[1];
        }
        orderedRoots.emplace_back(from, root);
    }
    std::sort(orderedRoots.begin(), orderedRoots.end());
    std::unordered_map<int, int> sectorOfRoot;
    for (const auto& [from, root] : orderedRoots) {
        const auto& tips = tipsOfRoot[root];
        const int first = from < tipCount ? from : tips[0];
        sphere.sectorTips.push_back({first, first == tips[0] ? tips[1] : tips[0]});
        sectorOfRoot[root] = static_cast<int>(sectorOfRoot.size());
    }
    std::unordered_map<std::uint64_t, int> sectorAround;  // off the slit and off the tips
    std::vector<int> sectorOfTriangle(triangleCount, -1);
    for (int t = 0; t < triangleCount; ++t) {
        if (!isFaceMissing(box, triangles[t].face)) continue;
        sectorOfTriangle[t] = sectorOfRoot[rootOf(parent, t)];
        for (const Lattice& corner : triangles[t].corners) {
            const std::uint64_t key = lattice.key(corner);
            if (slitRunsAt.count(key) == 0 && tipOfKey.count(key) == 0) sectorAround[key] = sectorOfTriangle[t];
        }
    }

    // Pass 2: the mesh. Vertices are keyed by their lattice index and, for slit copies, the
    // sector; a slit point (not a tip) has one copy per sector around it in Omega6.
    std::unordered_map<std::uint64_t, int> vertexOfKey;
    auto vertexAt = [&](const Lattice& index, int sector) {
        const std::uint64_t latticeKey = lattice.key(index);
        const std::uint64_t key = latticeKey * 16 + static_cast<std::uint64_t>(sector + 1);
        const auto [it, isNew] = vertexOfKey.emplace(key, static_cast<int>(sphere.mesh.positions.size()));
        if (isNew) {
            const glm::dvec3 point(sphere.gridLines[0][index[0]], sphere.gridLines[1][index[1]],
                                   sphere.gridLines[2][index[2]]);
            sphere.mesh.positions.push_back(glm::normalize(point - box.mapCentre));
            sphere.slitSector.push_back(sector);
            const auto around = sectorAround.find(latticeKey);
            sphere.missingSector.push_back(sector >= 0 ? sector : around != sectorAround.end() ? around->second : -1);
            sphere.lattice.push_back(index);
        }
        return it->second;
    };
    for (int t = 0; t < triangleCount; ++t) {
        const LatticeTriangle& lt = triangles[t];
        const bool isMissing = isFaceMissing(box, lt.face);
        if (isMissing && domain == SphereDomain::Display) continue;
        std::array<int, 3> triangle{};
        for (int c = 0; c < 3; ++c) {
            const std::uint64_t key = lattice.key(lt.corners[c]);
            const bool isCopied = isMissing && slitRunsAt.count(key) != 0 && tipOfKey.count(key) == 0;
            triangle[c] = vertexAt(lt.corners[c], isCopied ? sectorOfTriangle[t] : -1);
        }
        // Orient counter-clockwise seen from outside.
        const auto& p = sphere.mesh.positions;
        const glm::dvec3 normal = glm::cross(p[triangle[1]] - p[triangle[0]], p[triangle[2]] - p[triangle[0]]);
        if (glm::dot(normal, p[triangle[0]] + p[triangle[1]] + p[triangle[2]]) < 0.0) std::swap(triangle[1], triangle[2]);
        sphere.cellTriangles[lt.face][lt.cell] = static_cast<int>(sphere.mesh.triangles.size());
        sphere.mesh.triangles.push_back(triangle);
    }

    for (const int corner : tipCorners) sphere.cornerVertices.push_back(vertexAt(lattice.corner(corner), -1));
    int centreFace = 3;  // the floor
    for (const int face : {3, 5, 0, 1, 4, 2}) {
        if (!isFaceMissing(box, face)) {
            centreFace = face;
            break;
        }
    }
    sphere.nadirVertex = vertexAt(lattice.faceCentre(centreFace), -1);
    return sphere;
}

MeshLocation locateDirection(const SphereMesh& sphere, const glm::dvec3& direction) {
    const glm::dvec3 halfSize = 0.5 * sphere.box.size;
    const glm::dvec3& centre = sphere.box.mapCentre;
    // The face the ray leaves through: the smallest positive exit distance. On an edge of the
    // box two faces tie; prefer one that is meshed, so Omega5's boundary stays in Omega5.
    std::array<double, 3> exitAlong{};
    double exit = std::numeric_limits<double>::infinity();
    for (int axis = 0; axis < 3; ++axis) {
        exitAlong[axis] = std::numeric_limits<double>::infinity();
        if (direction[axis] == 0.0) continue;
        const double bound = direction[axis] > 0.0 ? halfSize[axis] : -halfSize[axis];
        exitAlong[axis] = (bound - centre[axis]) / direction[axis];
        exit = std::min(exit, exitAlong[axis]);
    }
    MeshLocation location;
    if (!std::isfinite(exit)) return location;
    int normalAxis = 0;
    bool isChosen = false;
    constexpr double kTie = 1e-12;
    for (int axis = 0; axis < 3 && !isChosen; ++axis) {
        if (!(exitAlong[axis] <= exit * (1.0 + kTie))) continue;
        normalAxis = axis;
        const int face = 2 * axis + (direction[axis] > 0.0 ? 0 : 1);
        isChosen = sphere.cellTriangles[face].empty() || sphere.cellTriangles[face].front() >= 0;
    }
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
