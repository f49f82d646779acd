#include "volumes/analytic_phantom.h"

#include <algorithm>
#include <cmath>

namespace volumes {
namespace {

/// Voxel value at signed distance `sdMm` (negative inside) from a surface: a linear ramp of
/// width `widthMm` centred on the surface between `insideHu` and `outsideHu`.
int16_t rampHu(double sdMm, double widthMm, int16_t insideHu, int16_t outsideHu) {
    const double insideFraction = std::clamp(0.5 - sdMm / widthMm, 0.0, 1.0);
    const double hu = outsideHu + insideFraction * (static_cast<double>(insideHu) - outsideHu);
    return static_cast<int16_t>(std::lround(hu));
}

/// Allocates an empty volume on `grid` and checks it before any voxel is written.
Volume allocate(const GridSpec& grid, const char* what) {
    Volume volume;
    volume.dims = grid.dims;
    volume.spacingMm = grid.spacingMm;
    if (grid.dims[0] < 1 || grid.dims[1] < 1 || grid.dims[2] < 1 || grid.dims[0] > kMaxDimension ||
        grid.dims[1] > kMaxDimension || grid.dims[2] > kMaxDimension) {
        throw VolumeError(std::string(what) + ": grid size outside 1.." + std::to_string(kMaxDimension));
    }
    volume.hu.resize(volume.voxelCount());
    validateVolume(volume, what);
    return volume;
}

}  // namespace

Volume makeBallPhantom(const BallSpec& spec) {
    if (!(spec.radiusMm > 0.0) || !(spec.edgeWidthMm > 0.0)) {
        throw VolumeError("ball phantom: radius and edge width must be positive");
    }
    Volume volume = allocate(spec.grid, "ball phantom");
    for (int k = 0; k < volume.dims[2]; ++k) {
        for (int j = 0; j < volume.dims[1]; ++j) {
            for (int i = 0; i < volume.dims[0]; ++i) {
                const glm::dvec3 p = glm::dvec3(i, j, k) * volume.spacingMm;
                const double sd = glm::length(p - spec.centreMm) - spec.radiusMm;
                volume.hu[volume.linearIndex(i, j, k)] =
                    rampHu(sd, spec.edgeWidthMm, spec.insideHu, spec.outsideHu);
            }
        }
    }
    return volume;
}

Volume makeTubePhantom(const TubeSpec& spec) {
    if (!(spec.radiusMm > 0.0) || !(spec.edgeWidthMm > 0.0)) {
        throw VolumeError("tube phantom: radius and edge width must be positive");
    }
    Volume volume = allocate(spec.grid, "tube phantom");
    for (int k = 0; k < volume.dims[2]; ++k) {
        for (int j = 0; j < volume.dims[1]; ++j) {
            for (int i = 0; i < volume.dims[0]; ++i) {
                const glm::dvec2 p = glm::dvec2(i * volume.spacingMm.x, j * volume.spacingMm.y);
                const double sd = glm::length(p - spec.axisMm) - spec.radiusMm;
                volume.hu[volume.linearIndex(i, j, k)] =
                    rampHu(sd, spec.edgeWidthMm, spec.lumenHu, spec.wallHu);
            }
        }
    }
    return volume;
}

}  // namespace volumes
