/// @brief Half-edge adjacency of a triangle mesh, built by sorting the directed edges.
#include "conformal/triangle_mesh.h"

#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace conformal {

namespace {

std::uint64_t directedEdgeKey(int from, int to) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(from)) << 32) |
           static_cast<std::uint32_t>(to);
}

}  // namespace

std::vector<int> twinHalfEdges(const TriangleMesh& mesh) {
    const std::size_t halfEdgeCount = 3 * mesh.triangles.size();
    std::vector<std::pair<std::uint64_t, int>> keyed(halfEdgeCount);
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        for (int e = 0; e < 3; ++e) {
            const int from = mesh.triangles[t][e];
            const int to = mesh.triangles[t][(e + 1) % 3];
            keyed[3 * t + e] = {directedEdgeKey(from, to), static_cast<int>(3 * t + e)};
        }
    }
    std::sort(keyed.begin(), keyed.end());
    for (std::size_t i = 1; i < keyed.size(); ++i) {
        if (keyed[i].first == keyed[i - 1].first) {
            throw std::runtime_error("triangle mesh: directed edge " +
                                     std::to_string(keyed[i].first >> 32) + " -> " +
                                     std::to_string(keyed[i].first & 0xffffffffu) +
                                     " is used twice (non-manifold or mis-oriented mesh)");
        }
    }
    std::vector<int> twins(halfEdgeCount, -1);
    for (std::size_t h = 0; h < halfEdgeCount; ++h) {
        const std::size_t t = h / 3;
        const int e = static_cast<int>(h % 3);
        const std::uint64_t reverse =
            directedEdgeKey(mesh.triangles[t][(e + 1) % 3], mesh.triangles[t][e]);
        const auto found = std::lower_bound(keyed.begin(), keyed.end(),
                                            std::make_pair(reverse, -1));
        if (found != keyed.end() && found->first == reverse) twins[h] = found->second;
    }
    return twins;
}

std::vector<char> boundaryVertexFlags(const TriangleMesh& mesh, const std::vector<int>& twins) {
    std::vector<char> isBoundary(mesh.positions.size(), 0);
    for (std::size_t h = 0; h < twins.size(); ++h) {
        if (twins[h] >= 0) continue;
        const std::size_t t = h / 3;
        const int e = static_cast<int>(h % 3);
        isBoundary[mesh.triangles[t][e]] = 1;
        isBoundary[mesh.triangles[t][(e + 1) % 3]] = 1;
    }
    return isBoundary;
}

}  // namespace conformal
