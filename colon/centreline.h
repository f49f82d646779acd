/// @brief The centreline of one tubular segment of lumen: a penalised-distance skeleton as in
/// the classic methods (Bitter et al., IEEE TVCG 2001; Wan et al., IEEE TMI 2002).
///
///  1. D: the distance of every lumen voxel from the wall (exact Euclidean, millimetres);
///  2. endpoints by farthest-point search: from the most central voxel, the voxel farthest
///     along the lumen (geodesic distance over the 26-neighbourhood) is one end A; the voxel
///     farthest from A is the other end B;
///  3. the path from A to B that minimises the sum of step length x (D_max / D)^2: steps near
///     the wall cost up to (D_max / D)^2 times more, so the path keeps to the middle and does
///     not cut corners through a bend;
///  4. the ends are trimmed where the path runs into the end caps (points nearer to their end
///     than their own distance from the wall), the voxel staircase is smoothed by a Gaussian
///     along the arc (smoothingMm), never out of the lumen, and resampled every stepMm.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "colon/grid.h"

namespace colon {

struct CentrelineSettings {
    double smoothingMm = 4.0;  ///< Gaussian sigma along the arc
    double stepMm = 1.0;       ///< spacing of the output points
};

struct SegmentCentreline {
    std::vector<glm::dvec3> pointsMm;  ///< volume millimetres, stepMm apart
    double lengthMm = 0.0;
    double meanRadiusMm = 0.0;  ///< the lumen's distance from the wall along the path
    double minRadiusMm = 0.0;
};

/// The centreline of the voxels of `labels` equal to `label` inside `box` (the segment's
/// bounding box); empty (no points, length 0) for a segment of under 3 voxels. Throws
/// ColonError for settings out of range.
SegmentCentreline centrelineOf(const Grid& grid, const std::vector<int32_t>& labels, int32_t label,
                               const VoxelBox& box, const CentrelineSettings& settings);

}  // namespace colon
