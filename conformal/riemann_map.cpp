/// @brief Riemann map onto the unit disk through a flat cylinder (Petkov et al. 2011, Sec. 4):
/// hole, Ricci flow, slice, layout, exponential map, hole filled at 0.
#include "conformal/riemann_map.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <numbers>
#include <stdexcept>
#include <string>
#include <unordered_set>

namespace conformal {

namespace {

using Complex = std::complex<double>;

std::uint64_t undirectedKey(int a, int b) {
    const auto lo = static_cast<std::uint64_t>(std::min(a, b));
    const auto hi = static_cast<std::uint64_t>(std::max(a, b));
    return (hi << 32) | lo;
}

/// The vertices' neighbours through the triangles' edges (compressed rows).
void vertexNeighbours(const TriangleMesh& mesh, std::vector<int>& offsets,
                      std::vector<int>& neighbours) {
    const std::size_t n = mesh.positions.size();
    offsets.assign(n + 1, 0);
    for (const auto& tri : mesh.triangles) {
        for (int k = 0; k < 3; ++k) offsets[tri[k] + 1] += 2;
    }
    for (std::size_t v = 0; v < n; ++v) offsets[v + 1] += offsets[v];
    neighbours.assign(offsets[n], -1);
    std::vector<int> fill(offsets.begin(), offsets.end() - 1);
    for (const auto& tri : mesh.triangles) {
        for (int k = 0; k < 3; ++k) {
            neighbours[fill[tri[k]]++] = tri[(k + 1) % 3];
            neighbours[fill[tri[k]]++] = tri[(k + 2) % 3];
        }
    }
}

}  // namespace

std::vector<Complex> diskFromMesh(const TriangleMesh& mesh, int centreVertex,
                                  const RicciFlowSettings& settings, RiemannMapReport* report) {
    const int vertexCount = static_cast<int>(mesh.positions.size());
    if (centreVertex < 0 || centreVertex >= vertexCount) {
        throw std::runtime_error("Riemann map: centre vertex " + std::to_string(centreVertex) +
                                 " is not a vertex of the mesh");
    }

    // Punch the hole: drop the centre's star, keep the other vertices' indices.
    TriangleMesh punched;
    punched.positions = mesh.positions;
    punched.triangles.reserve(mesh.triangles.size());
    for (const auto& tri : mesh.triangles) {
        if (tri[0] != centreVertex && tri[1] != centreVertex && tri[2] != centreVertex) {
            punched.triangles.push_back(tri);
        }
    }
    if (punched.triangles.size() == mesh.triangles.size()) {
        throw std::runtime_error("Riemann map: centre vertex " + std::to_string(centreVertex) +
                                 " belongs to no triangle");
    }
    std::vector<char> isHoleRing(vertexCount, 0);
    for (const auto& tri : mesh.triangles) {
        if (tri[0] == centreVertex || tri[1] == centreVertex || tri[2] == centreVertex) {
            for (int v : tri) {
                if (v != centreVertex) isHoleRing[v] = 1;
            }
        }
    }
    // The centre vertex is isolated now; keep it out of the flow by giving it no triangles
    // (its curvature target is irrelevant, and it is pinned if chosen, so drop it instead).
    TriangleMesh flowMesh;
    std::vector<int> flowIndex(vertexCount, -1);
    std::vector<int> originalIndex;
    originalIndex.reserve(vertexCount);
    for (int v = 0; v < vertexCount; ++v) {
        if (v == centreVertex) continue;
        flowIndex[v] = static_cast<int>(originalIndex.size());
        originalIndex.push_back(v);
        flowMesh.positions.push_back(mesh.positions[v]);
    }
    flowMesh.triangles.reserve(punched.triangles.size());
    for (const auto& tri : punched.triangles) {
        flowMesh.triangles.push_back({flowIndex[tri[0]], flowIndex[tri[1]], flowIndex[tri[2]]});
    }
    const std::vector<int> twins = twinHalfEdges(flowMesh);
    const std::vector<char> isBoundary = boundaryVertexFlags(flowMesh, twins);
    const int flowCount = static_cast<int>(flowMesh.positions.size());
    std::vector<char> isInner(flowCount, 0);
    for (int v = 0; v < flowCount; ++v) isInner[v] = isHoleRing[originalIndex[v]];
    for (int v = 0; v < flowCount; ++v) {
        if (isInner[v] && !isBoundary[v]) {
            throw std::runtime_error("Riemann map: the hole's rim is not a boundary loop");
        }
    }

    // Flat cylinder: zero curvature at every vertex, so both boundaries become geodesics.
    RiemannMapReport localReport;
    RiemannMapReport& out = report ? *report : localReport;
    out.flow = flowToTargetCurvature(flowMesh, std::vector<double>(flowCount, 0.0), settings);
    const auto& lengths = out.flow.edgeLengths;
    const auto& angles = out.flow.cornerAngles;

    // Slice: a shortest edge path (fewest edges) from the hole's rim to the outer boundary
    // through interior vertices.
    std::vector<int> offsets;
    std::vector<int> neighbours;
    vertexNeighbours(flowMesh, offsets, neighbours);
    std::vector<int> parent(flowCount, -2);
    std::deque<int> queue;
    for (int v = 0; v < flowCount; ++v) {
        if (isInner[v]) {
            parent[v] = -1;
            queue.push_back(v);
        }
    }
    int outerEnd = -1;
    while (!queue.empty() && outerEnd < 0) {
        const int v = queue.front();
        queue.pop_front();
        for (int i = offsets[v]; i < offsets[v + 1]; ++i) {
            const int w = neighbours[i];
            if (parent[w] != -2) continue;
            if (isBoundary[w] && !isInner[w]) {
                parent[w] = v;
                outerEnd = w;
                break;
            }
            if (isBoundary[w]) continue;
            parent[w] = v;
            queue.push_back(w);
        }
    }
    if (outerEnd < 0) throw std::runtime_error("Riemann map: no path from the hole to the boundary");
    std::unordered_set<std::uint64_t> cutEdges;
    for (int v = outerEnd; parent[v] >= 0; v = parent[v]) cutEdges.insert(undirectedKey(v, parent[v]));

    // Layout: place triangles breadth-first across uncut edges; positions per corner.
    const std::size_t triangleCount = flowMesh.triangles.size();
    std::vector<std::array<Complex, 3>> corner(triangleCount);
    std::vector<char> isPlaced(triangleCount, 0);
    std::deque<int> triangleQueue;
    corner[0][0] = Complex(0.0, 0.0);
    corner[0][1] = Complex(lengths[0][2], 0.0);
    corner[0][2] = std::polar(lengths[0][1], angles[0][0]);
    isPlaced[0] = 1;
    triangleQueue.push_back(0);
    std::size_t placedCount = 1;
    while (!triangleQueue.empty()) {
        const int t = triangleQueue.front();
        triangleQueue.pop_front();
        for (int e = 0; e < 3; ++e) {
            const int twin = twins[3 * t + e];
            if (twin < 0) continue;
            const int s = twin / 3;
            if (isPlaced[s]) continue;
            const auto& tri = flowMesh.triangles[t];
            const int a = tri[e];
            const int b = tri[(e + 1) % 3];
            if (cutEdges.count(undirectedKey(a, b))) continue;
            // In s the edge runs b -> a (corner f to f + 1); its third corner g lies to the left
            // of b -> a, at the angle of s at b.
            const int f = twin % 3;
            const int g = (f + 2) % 3;
            const Complex pb = corner[t][(e + 1) % 3];
            const Complex pa = corner[t][e];
            const Complex direction = (pa - pb) / std::abs(pa - pb);
            corner[s][f] = pb;
            corner[s][(f + 1) % 3] = pa;
            // Edge b -> g is opposite corner (f + 1).
            corner[s][g] = pb + lengths[s][(f + 1) % 3] * direction * std::polar(1.0, angles[s][f]);
            isPlaced[s] = 1;
            ++placedCount;
            triangleQueue.push_back(s);
        }
    }
    if (placedCount != triangleCount) {
        throw std::runtime_error("Riemann map: the sliced mesh is not connected (" +
                                 std::to_string(placedCount) + " of " +
                                 std::to_string(triangleCount) + " triangles laid out)");
    }

    // The translation T between the slice's two sides.
    Complex translation(0.0, 0.0);
    {
        const int a = outerEnd;
        const int b = parent[outerEnd];
        for (std::size_t t = 0; t < triangleCount && translation == Complex(0.0, 0.0); ++t) {
            for (int e = 0; e < 3; ++e) {
                const auto& tri = flowMesh.triangles[t];
                if (tri[e] != a || tri[(e + 1) % 3] != b) continue;
                const int twin = twins[3 * t + e];
                if (twin < 0) break;
                translation = corner[t][e] - corner[twin / 3][(twin % 3 + 1) % 3];
                break;
            }
        }
    }
    if (std::abs(translation) == 0.0) throw std::runtime_error("Riemann map: the slice has no width");

    // Straighten the cylinder: zeta = 2 pi i z / T is periodic by 2 pi i; the outer boundary is
    // a vertical line, sent to the unit circle by exp.
    const Complex scale = Complex(0.0, 2.0 * std::numbers::pi) / translation;
    double innerSum = 0.0;
    double outerSum = 0.0;
    int innerCount = 0;
    int outerCount = 0;
    for (std::size_t t = 0; t < triangleCount; ++t) {
        for (int k = 0; k < 3; ++k) {
            const int v = flowMesh.triangles[t][k];
            if (!isBoundary[v]) continue;
            const double re = (scale * corner[t][k]).real();
            if (isInner[v]) {
                innerSum += re;
                ++innerCount;
            } else {
                outerSum += re;
                ++outerCount;
            }
        }
    }
    const double sign = innerSum / innerCount > outerSum / outerCount ? -1.0 : 1.0;
    const double outerRe = sign * outerSum / outerCount;

    std::vector<Complex> disk(vertexCount, Complex(0.0, 0.0));
    std::vector<int> copies(vertexCount, 0);
    std::vector<Complex> firstCopy(vertexCount);
    out.seamMismatch = 0.0;
    for (std::size_t t = 0; t < triangleCount; ++t) {
        for (int k = 0; k < 3; ++k) {
            const int v = originalIndex[flowMesh.triangles[t][k]];
            const Complex w = std::exp(sign * scale * corner[t][k] - outerRe);
            if (copies[v] == 0) firstCopy[v] = w;
            out.seamMismatch = std::max(out.seamMismatch, std::abs(w - firstCopy[v]));
            disk[v] += w;
            ++copies[v];
        }
    }
    out.outerRadiusError = 0.0;
    double innerRadiusSum = 0.0;
    for (int v = 0; v < vertexCount; ++v) {
        if (copies[v] > 0) disk[v] /= static_cast<double>(copies[v]);
        if (v == centreVertex) continue;
        const int f = flowIndex[v];
        if (isBoundary[f] && !isInner[f]) {
            out.outerRadiusError = std::max(out.outerRadiusError, std::abs(std::abs(disk[v]) - 1.0));
        } else if (isInner[f]) {
            innerRadiusSum += std::abs(disk[v]);
        }
    }
    int ringCount = 0;
    for (int v = 0; v < flowCount; ++v) ringCount += isInner[v];
    out.innerRadius = innerRadiusSum / std::max(ringCount, 1);
    disk[centreVertex] = Complex(0.0, 0.0);
    return disk;
}

}  // namespace conformal
