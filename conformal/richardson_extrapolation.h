/// @brief Richardson extrapolation of a disk map from a mesh and its half-resolution companion:
/// the Ricci-flow map's vertex error is smooth and O(h^2), so 4/3 f_h - 1/3 f_2h cancels it.
#pragma once

#include <complex>
#include <vector>

#include "conformal/sphere_mesh.h"

namespace conformal {

/// Returns f*(v) = f_h(v) + (f_h(v) - f_2h(v)) / 3 for every vertex v of `fine`. The difference
/// f_h - f_2h is exact at the vertices the meshes share (every other grid line) and is
/// interpolated along grid lines elsewhere (its second derivatives are O(h^2), so this costs
/// O(h^4)); copies along the slit keep to their own side. `coarse` must have been built with
/// the same box and settings as `fine` but coarsening 2. Throws std::invalid_argument if the
/// meshes do not match.
std::vector<std::complex<double>> extrapolateFromCoarse(const SphereMesh& fine,
                                                        const std::vector<std::complex<double>>& fineDisk,
                                                        const SphereMesh& coarse,
                                                        const std::vector<std::complex<double>>& coarseDisk);

}  // namespace conformal
