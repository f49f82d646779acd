/// @brief Richardson extrapolation and prolongation over the box lattice shared by a mesh and
/// its coarse companion.
#include "conformal/richardson_extrapolation.h"

#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <unordered_map>

namespace conformal {

namespace {

using Complex = std::complex<double>;

std::uint64_t latticeKey(const std::array<int, 3>& lattice, int sector) {
    return ((static_cast<std::uint64_t>(lattice[0]) * 65536 + static_cast<std::uint64_t>(lattice[1])) * 65536 +
            static_cast<std::uint64_t>(lattice[2])) * 16 +
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

/// The vertex at `lattice`: its single copy, or on the slit the copy of `sector`.
std::unordered_map<std::uint64_t, int>::const_iterator findVertex(const std::unordered_map<std::uint64_t, int>& index,
                                                                   const std::array<int, 3>& lattice, int sector) {
    const auto single = index.find(latticeKey(lattice, -1));
    return single != index.end() || sector < 0 ? single : index.find(latticeKey(lattice, sector));
}

}  // namespace

LatticeParents latticeParents(const SphereMesh& fine, const SphereMesh& coarse) {
    for (int axis = 0; axis < 3; ++axis) {
        if (fine.gridLines[axis].size() != 2 * coarse.gridLines[axis].size() - 1) {
            throw std::invalid_argument("Richardson extrapolation: the coarse mesh does not have "
                                        "every other grid line of the fine mesh");
        }
    }
    const auto fineIndex = indexByLattice(fine);
    const auto coarseIndex = indexByLattice(coarse);

    LatticeParents parents;
    const std::size_t n = fine.mesh.positions.size();
    parents.fineIndex.assign(n, {-1, -1, -1, -1});
    parents.coarseIndex.assign(n, {-1, -1, -1, -1});
    parents.count.assign(n, 0);
    // Records a vertex both meshes share as a parent of fine vertex v; on the slit, the copy on
    // v's side (its sector).
    auto addParent = [&](std::size_t v, const std::array<int, 3>& lattice, int sector) {
        const auto f = findVertex(fineIndex, lattice, sector);
        const std::array<int, 3> coarseLattice = {lattice[0] / 2, lattice[1] / 2, lattice[2] / 2};
        const auto c = findVertex(coarseIndex, coarseLattice, sector);
        if (f == fineIndex.end() || c == coarseIndex.end()) {
            throw std::invalid_argument("Richardson extrapolation: a shared vertex is missing");
        }
        const int k = parents.count[v]++;
        parents.fineIndex[v][k] = f->second;
        parents.coarseIndex[v][k] = c->second;
    };
    // The slit run through a lattice point strictly between two of its lattice steps' ends.
    auto slitStepAt = [&](const std::array<int, 3>& lattice) -> std::array<int, 3> {
        for (const SlitSegment& run : fine.slit) {
            int k = 0;
            bool isKnown = false;
            bool isOn = true;
            for (int a = 0; a < 3 && isOn; ++a) {
                const int offset = lattice[a] - run.from[a];
                if (run.step[a] == 0) {
                    isOn = offset == 0;
                } else if (!isKnown) {
                    k = offset * run.step[a];
                    isKnown = true;
                } else {
                    isOn = offset * run.step[a] == k;
                }
            }
            if (isOn && k > 0 && k < run.steps) return run.step;
        }
        throw std::invalid_argument("Richardson extrapolation: a slit vertex lies on no slit run");
    };

    for (std::size_t v = 0; v < n; ++v) {
        const auto& lattice = fine.lattice[v];
        const int sector = fine.slitSector[v];
        const bool isShared = lattice[0] % 2 == 0 && lattice[1] % 2 == 0 && lattice[2] % 2 == 0;
        if (isShared) {
            addParent(v, lattice, sector);
        } else if (sector >= 0) {
            // On the slit: the two neighbours along its run, on this copy's side.
            const std::array<int, 3> step = slitStepAt(lattice);
            addParent(v, {lattice[0] - step[0], lattice[1] - step[1], lattice[2] - step[2]}, sector);
            addParent(v, {lattice[0] + step[0], lattice[1] + step[1], lattice[2] + step[2]}, sector);
        } else {
            // The neighbours on the odd grid lines: 2 along an edge, 4 in a cell.
            const int ownSector = fine.missingSector[v];
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
                        if (!isDuplicate) addParent(v, p, ownSector);
                    }
                }
            }
        }
    }
    return parents;
}

std::vector<Complex> extrapolateFromCoarse(const LatticeParents& parents, const std::vector<Complex>& fineDisk,
                                           const std::vector<Complex>& coarseDisk) {
    std::vector<Complex> result(fineDisk.size());
    for (std::size_t v = 0; v < fineDisk.size(); ++v) {
        Complex difference(0.0);
        for (int k = 0; k < parents.count[v]; ++k) {
            difference += fineDisk[parents.fineIndex[v][k]] - coarseDisk[parents.coarseIndex[v][k]];
        }
        result[v] = fineDisk[v] + difference / (3.0 * parents.count[v]);
    }
    return result;
}

std::vector<double> prolongFromCoarse(const LatticeParents& parents, const std::vector<double>& coarseValues) {
    std::vector<double> result(parents.count.size(), std::numeric_limits<double>::quiet_NaN());
    for (std::size_t v = 0; v < result.size(); ++v) {
        double sum = 0.0;
        int used = 0;
        for (int k = 0; k < parents.count[v]; ++k) {
            const double value = coarseValues[parents.coarseIndex[v][k]];
            if (std::isnan(value)) continue;
            sum += value;
            ++used;
        }
        if (used > 0) result[v] = sum / used;
    }
    return result;
}

}  // namespace conformal
