/// @brief Analytic phantoms (a ball, a straight tube) whose surfaces are known in closed form,
/// for tests of the renderer and for the first-light demo.
#pragma once

#include <array>

#include "volumes/volume.h"

namespace volumes {

/// A voxel grid in volume millimetres (voxel (i,j,k) centred at (i,j,k) * spacingMm).
struct GridSpec {
    std::array<int, 3> dims{128, 128, 128};
    glm::dvec3 spacingMm{1.0, 1.0, 1.0};
};

/// A solid ball of `insideHu` in a background of `outsideHu`. Across the surface the value
/// ramps linearly over `edgeWidthMm`, so the iso value halfway between the two HU lies on the
/// analytic sphere |p - centreMm| = radiusMm (the ramp stands in for the partial-volume blur
/// of a real scanner).
struct BallSpec {
    GridSpec grid;
    glm::dvec3 centreMm{63.5, 63.5, 63.5};
    double radiusMm = 40.0;
    int16_t insideHu = 1000;
    int16_t outsideHu = -1000;
    double edgeWidthMm = 2.0;
};

/// An air-filled straight tube (a colon with nothing in it) along the z axis through
/// `axisMm` (x, y), lumen `lumenHu`, surrounded by `wallHu`, with the same linear edge ramp
/// as BallSpec so the half-way iso value lies on the cylinder |(x, y) - axisMm| = radiusMm.
struct TubeSpec {
    GridSpec grid;
    glm::dvec2 axisMm{63.5, 63.5};
    double radiusMm = 30.0;
    int16_t lumenHu = -1000;
    int16_t wallHu = 40;
    double edgeWidthMm = 2.0;
};

/// Samples the ball at every voxel centre. Throws VolumeError for a grid validateVolume rejects.
Volume makeBallPhantom(const BallSpec& spec);

/// Samples the tube at every voxel centre. Throws VolumeError for a grid validateVolume rejects.
Volume makeTubePhantom(const TubeSpec& spec);

}  // namespace volumes
