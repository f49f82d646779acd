/// @brief A synthetic polyp inserted into a real CT (or any volume) on the colon wall nearest a
/// point, with its ground truth in the colon phantom's form (volumes/colon_phantom.h).
///
/// The polyp is made to look like the scan, not like the phantom: its value is the wall's own
/// tissue HU measured beneath the surface, and its edge is blurred as much as the scan blurs the
/// wall there (the 10%-90% width of the HU profile across the wall), so a detector cannot tell
/// it from the scan's resolution. Geometry is the phantom's: a sessile polyp is a sphere centred
/// on the wall surface, a pedunculated one a sphere on a capsule stalk along the wall normal.
///
/// Steps (all in volume millimetres, HU sampled trilinearly between voxel centres):
///  1. the point must lie in air (its nearest voxel below kLumenAirHu);
///  2. the nearest voxel at or above isoHu within kWallSearchMm; the wall surface point is the
///     isoHu crossing on the segment from the point to it (bisection), the wall normal minus the
///     HU gradient there (a least-squares plane through the voxels around it), into the lumen;
///  3. tissue HU: the median of voxels 1.5..5 mm beneath the surface around it that are soft
///     tissue (-200..300 HU); air HU the same above it; the edge width: the ramp whose sampled
///     profile rises 10%-90% over the same distance as the scan's across the wall there;
///  4. every voxel of the polyp's box gets w = clamp(0.5 - sdf / edge, 0, 1) of the way from its
///     value to the tissue HU, where that raises it (air and partial volume become polyp; the
///     wall is never lowered).
#pragma once

#include <cstddef>

#include <glm/glm.hpp>

#include "volumes/colon_phantom.h"
#include "volumes/volume.h"

namespace colon {

/// What to insert, and where.
struct PolypInsertion {
    glm::dvec3 atMm{0.0};        ///< a point in the lumen; the polyp goes on the wall nearest to it
    double diameterMm = 6.0;     ///< 3..30 mm; the head's diameter for a pedunculated polyp
    double stalkLengthMm = 0.0;  ///< 0: sessile; > 0: pedunculated, wall surface to the head's surface
    double isoHu = -500.0;       ///< the air/wall surface value (the renderer's iso value)
};

/// A voxel nearer than this to the point (its nearest voxel) must be below it to count as lumen.
inline constexpr double kLumenAirHu = -800.0;
/// The wall is looked for within this distance of the point.
inline constexpr double kWallSearchMm = 30.0;
inline constexpr double kMinPolypDiameterMm = 3.0;
inline constexpr double kMaxPolypDiameterMm = 30.0;
/// A polyp must be at least this many voxels (of the largest spacing) across.
inline constexpr double kMinPolypVoxelsAcross = 4.0;

/// The inserted polyp's ground truth (truth.arcLengthMm is left 0: the volume has no centreline
/// here) and what the scan looked like where it went.
struct InsertedPolyp {
    volumes::PolypTruth truth;
    double tissueHu = 0.0;     ///< the polyp's value: the wall's median soft-tissue HU beneath the base
    double airHu = 0.0;        ///< the lumen's median HU above the base
    double wallBlurMm = 0.0;   ///< the scan's 10%-90% rise across the wall at the base (trilinear HU)
    double edgeWidthMm = 0.0;  ///< the polyp's ramp: w goes 1 -> 0 over this width, so it blurs as wallBlurMm
    glm::dvec3 stalkStartMm{0.0};  ///< pedunculated only: the stalk's axis, from inside the wall...
    glm::dvec3 stalkEndMm{0.0};    ///< ...to the head's centre
    double stalkRadiusMm = 0.0;    ///< 0 for a sessile polyp
    std::size_t voxelsChanged = 0;

    /// Signed distance (mm) from `pointMm` to the polyp's solid, negative inside.
    [[nodiscard]] double signedDistanceMm(const glm::dvec3& pointMm) const;
};

/// Inserts the polyp into `volume` in place and returns its truth. Throws ColonError (one line,
/// naming the problem) for a point that is not finite, outside the volume or not in the lumen,
/// no wall within kWallSearchMm, a diameter outside 3..30 mm or under 4 voxels across, a polyp
/// that would reach past the opposite wall or outside the volume, or a wall that cannot be
/// measured (no soft tissue beneath it, no HU gradient, no edge across it).
InsertedPolyp insertPolyp(volumes::Volume& volume, const PolypInsertion& request);

}  // namespace colon
