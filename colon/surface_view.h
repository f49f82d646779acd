/// @brief A small pinhole view of the iso-surface, cast on the CPU: the first hit of each
/// pixel's ray, as `cvc render --hits` writes it (colon/hit_image.h), so a surface can be
/// measured (colon/surface_measure.h) and shown where no Vulkan device is wanted. Each ray
/// marches at a quarter of the finest voxel spacing from the eye (which must lie in air) to
/// the first sample at or above the iso value, then bisects the crossing on the trilinear HU,
/// as the renderer's refinement does. Meant for views of a few hundred pixels a side.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "colon/hit_image.h"
#include "volumes/volume.h"

namespace colon {

struct SurfaceViewRequest {
    glm::dvec3 eyeMm{0.0};
    glm::dvec3 lookAtMm{0.0, 0.0, 1.0};
    glm::dvec3 up{0.0, 1.0, 0.0};  ///< made orthogonal to the view; must not be parallel to it
    double fovDeg = 40.0;          ///< vertical and horizontal (square pixels, square image)
    int size = 128;                ///< pixels per side, 8..1024
    double isoHu = -500.0;
    double maxDistanceMm = 200.0;  ///< a ray that meets no surface within this is a miss
};

/// The first hits of a size x size pinhole view (row 0 at the top, +x to the right of the view).
/// Throws ColonError for a size out of range, a non-finite or degenerate camera, or an eye at
/// or above the iso value (inside tissue, where no ray would leave the surface).
HitImage surfaceView(const volumes::Volume& volume, const SurfaceViewRequest& request);

/// A grey picture of `image` for a person to look at: each hit lit from the eye by its normal
/// (estimated from the neighbouring hits), misses black; RGBA, row 0 at the top.
std::vector<uint8_t> shadedSurfaceView(const HitImage& image, const glm::dvec3& eyeMm);

}  // namespace colon
