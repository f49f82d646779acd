/// @brief The exact Euclidean distance transform of a voxel mask with anisotropic spacing.
///
/// Felzenszwalb and Huttenlocher's separable algorithm ("Distance Transforms of Sampled
/// Functions", Theory of Computing 2012): three passes of the 1D lower envelope of parabolas,
/// one per axis, each weighted by that axis's spacing, so 0.7 x 0.7 x 3 mm voxels get true
/// millimetre distances. OpenVDB's level-set tools assume cubic voxels and a narrow band; the
/// centreline needs the distance deep inside a lumen of any voxel shape, so it is computed here.
#pragma once

#include <cstdint>
#include <vector>

#include "colon/grid.h"

namespace colon {

/// For every voxel with inside[n] != 0, the distance in millimetres from its centre to the
/// centre of the nearest voxel with inside == 0 (voxels beyond the grid count as outside);
/// 0 for outside voxels.
std::vector<float> distanceToOutsideMm(const Grid& grid, const std::vector<uint8_t>& inside);

}  // namespace colon
