/// @brief Transfers between a sphere mesh and its half-resolution companion (every other grid
/// line): Richardson extrapolation of a disk map, whose vertex error is smooth and O(h^2) so
/// that f_h + (f_h - f_2h) / 3 cancels it, and prolongation of coarse vertex data to start
/// the fine flow near its solution.
#pragma once

#include <array>
#include <complex>
#include <vector>

#include "conformal/sphere_mesh.h"

namespace conformal {

/// For each vertex of the fine mesh, the shared vertices (1, 2 or 4, on the coarse lattice)
/// whose average stands for it: itself when shared, else its neighbours along the odd grid
/// lines; copies along the slit keep to their own side.
struct LatticeParents {
    std::vector<std::array<int, 4>> fineIndex;    ///< parents as fine-mesh vertices
    std::vector<std::array<int, 4>> coarseIndex;  ///< the same parents as coarse-mesh vertices
    std::vector<int> count;                       ///< 1, 2 or 4 per fine vertex
};

/// Throws std::invalid_argument unless `coarse` was built like `fine` with coarsening 2.
LatticeParents latticeParents(const SphereMesh& fine, const SphereMesh& coarse);

/// f*(v) = f_h(v) + (f_h - f_2h)(v) / 3, the difference taken at the parents (exact where
/// shared, averaged along grid lines elsewhere: its second derivatives are O(h^2), so this
/// costs O(h^4)).
std::vector<std::complex<double>> extrapolateFromCoarse(const LatticeParents& parents,
                                                        const std::vector<std::complex<double>>& fineDisk,
                                                        const std::vector<std::complex<double>>& coarseDisk);

/// Coarse vertex values averaged onto the fine mesh; NaN parents are skipped (NaN if all are).
std::vector<double> prolongFromCoarse(const LatticeParents& parents, const std::vector<double>& coarseValues);

}  // namespace conformal
