/// @brief Richardson extrapolation over the box lattice shared by a mesh and its coarse
/// companion.
#include "conformal/richardson_extrapolation.h"

#include <cstdint>
#include <stdexcept>
#include <unordered_map>

namespace conformal {

namespace {

using Complex = std::complex<double>;

std::uint64_t latticeKey(const std::array<int, 3>& lattice, int sector) {
    return ((static_cast<std::uint64_t>(lattice[0]) * 65536 + static_cast<std::uint64_t>(lattice[1])) * 65536 +
            static_cast<std::uint64_t>(lattice[2])) * 8 +
           static_cast<std::uint64_t>(sector + 1);
}

std::unordered_map<std::uint64_t, int> indexByLattice(const SphereMesh& mesh) {
    std::unordered_map<std::uint64_t, int> index;
    index.reserve(mesh.lattice.size());
    for (std::size_t v = 0; v < mesh.lattice.size(); ++v) {
        index.emplace(latticeKey(mesh.lattice[v], mesh.slitSector[v]), static_cast<int>(v));
    }
    return index;
}

}  // namespace

std::vector<Complex> extrapolateFromCoarse(const SphereMesh& fine, const std::vector<Complex>& fineDisk,
                                           const SphereMesh& coarse, const std::vector<Complex>& coarseDisk) {
    for (int axis = 0; axis < 3; ++axis) {
        if (fine.gridLines[axis].size() != 2 * coarse.gridLines[axis].size() - 1) {
            throw std::invalid_argument("Richardson extrapolation: the coarse mesh does not have "
                                        "every other grid line of the fine mesh");
        }
    }
    const auto fineIndex = indexByLattice(fine);
    const auto coarseIndex = indexByLattice(coarse);
    const int half = static_cast<int>(fine.gridLines[0].size() - 1) / 2;
    const int top = static_cast<int>(fine.gridLines[1].size() - 1);

    // The difference f_h - f_2h at a vertex both meshes share.
    auto differenceAt = [&](const std::array<int, 3>& lattice, int sector) {
        const auto f = fineIndex.find(latticeKey(lattice, sector));
        const std::array<int, 3> coarseLattice = {lattice[0] / 2, lattice[1] / 2, lattice[2] / 2};
        const auto c = coarseIndex.find(latticeKey(coarseLattice, sector));
        if (f == fineIndex.end() || c == coarseIndex.end()) {
            throw std::invalid_argument("Richardson extrapolation: a shared vertex is missing");
        }
        return fineDisk[f->second] - coarseDisk[c->second];
    };
    // A ceiling vertex on a diagonal (but not a corner) exists once per sector.
    auto isSlitPoint = [&](const std::array<int, 3>& lattice) {
        const int dx = lattice[0] - half;
        const int dz = lattice[2] - half;
        return lattice[1] == top && std::abs(dx) == std::abs(dz) && std::abs(dx) != half;
    };

    std::vector<Complex> result(fineDisk.size());
    for (std::size_t v = 0; v < fineDisk.size(); ++v) {
        const auto& lattice = fine.lattice[v];
        const int sector = fine.slitSector[v];
        Complex difference(0.0);
        const bool isShared = lattice[0] % 2 == 0 && lattice[1] % 2 == 0 && lattice[2] % 2 == 0;
        if (isShared) {
            difference = differenceAt(lattice, sector);
        } else if (sector >= 0) {
            // On the slit: interpolate along the diagonal, on this copy's side.
            const int sx = lattice[0] > half ? 1 : -1;
            const int sz = lattice[2] > half ? 1 : -1;
            const std::array<int, 3> inner = {lattice[0] - sx, lattice[1], lattice[2] - sz};
            const std::array<int, 3> outer = {lattice[0] + sx, lattice[1], lattice[2] + sz};
            difference = 0.5 * (differenceAt(inner, isSlitPoint(inner) ? sector : -1) +
                                differenceAt(outer, isSlitPoint(outer) ? sector : -1));
        } else {
            // Average over the neighbours on the odd grid lines: 2 along an edge, 4 in a cell.
            const int ownSector = lattice[1] == top
                                      ? ceilingSectorOf(lattice[0] - half, lattice[2] - half)
                                      : -1;
            int parents = 0;
            for (int ox = -1; ox <= 1; ox += 2) {
                for (int oy = -1; oy <= 1; oy += 2) {
                    for (int oz = -1; oz <= 1; oz += 2) {
                        std::array<int, 3> p = lattice;
                        const std::array<int, 3> offset = {ox, oy, oz};
                        bool isDuplicate = false;
                        for (int a = 0; a < 3; ++a) {
                            if (lattice[a] % 2 != 0) {
                                p[a] += offset[a];
                            } else if (offset[a] > 0) {
                                isDuplicate = true;  // even axes contribute one offset only
                            }
                        }
                        if (isDuplicate) continue;
                        difference += differenceAt(p, isSlitPoint(p) ? ownSector : -1);
                        ++parents;
                    }
                }
            }
            difference /= static_cast<double>(parents);
        }
        result[v] = fineDisk[v] + difference / 3.0;
    }
    return result;
}

}  // namespace conformal
