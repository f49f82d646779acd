/// @brief Which air in a CT is the colon: air by threshold, connected regions, and documented
/// rules that set aside the air outside the body, the lungs, small pockets and round (not
/// tubular) air such as the stomach's.
///
/// Rules, in order (measured on the shared abdominal CT and the phantoms: docs/colon.md):
///  1. air: HU below airThresholdHu (-800: colonic gas is about -1000 HU, soft tissue above
///     -200, so the threshold sits well inside the gap even with partial volume and noise);
///  2. outside: a region touching a face of the volume other than the two across the
///     patient's head-foot axis (the air around the body and under the table reaches the
///     sides; a colon cut by the scan's field of view reaches the top or bottom face only);
///  3. small: under minRegionMl (gas in the small bowel, noise);
///  4. lung: median HU above lungMedianHu (lung parenchyma is air mixed with tissue,
///     -850 HU and up; insufflated colonic gas stays near -1000 HU);
///  5. round: tubularity under minTubularity, where tubularity = volume / (2 pi r^3) with r the
///     region's largest inscribed radius: the region's length in diameters for a tube, 0.67 for
///     a ball (the stomach's gas bubble, a gas pocket);
///  6. colon: the rest.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "colon/grid.h"
#include "volumes/volume.h"

namespace colon {

struct SegmentationSettings {
    double airThresholdHu = -800.0;
    double minRegionMl = 2.0;
    double lungMedianHu = -900.0;
    double minTubularity = 2.0;
};

enum class AirClass { Outside, Small, Lung, Round, Colon };

/// The name used in reports: "outside", "small", "lung", "round", "colon".
const char* airClassName(AirClass kind);

/// One connected region of air with the measures the rules use.
struct AirRegion {
    int32_t label = 0;
    AirClass kind = AirClass::Outside;
    std::size_t voxels = 0;
    double volumeMl = 0.0;
    double medianHu = 0.0;
    double maxRadiusMm = 0.0;  ///< largest inscribed ball's radius (0 where not measured)
    double tubularity = 0.0;   ///< volume / (2 pi r^3) (0 where not measured)
    glm::dvec3 centroidMm{0.0};
    VoxelBox box;
};

/// Air regions and the label of every voxel (0: not air; otherwise the region's label).
struct AirSegmentation {
    Grid grid;
    std::vector<int32_t> labels;
    std::vector<AirRegion> regions;  ///< largest first
};

/// The voxel axis (0, 1 or 2) closest to a direction of the patient frame (LPS), from the
/// volume's orientation matrix, and the sign of a voxel step along it that goes that way.
struct VoxelAxis {
    int axis = 2;
    int sign = 1;
};
VoxelAxis voxelAxisAlong(const volumes::Volume& volume, const glm::dvec3& directionLps);

/// Patient-frame directions the analysis orients itself by.
inline constexpr glm::dvec3 kSuperiorLps{0.0, 0.0, 1.0};
inline constexpr glm::dvec3 kPosteriorLps{0.0, 1.0, 0.0};  ///< gravity for a supine patient
inline constexpr glm::dvec3 kAnteriorLps{0.0, -1.0, 0.0};

/// Segments the air of `volume` and classifies every region by the rules above. Throws
/// ColonError for settings out of range.
AirSegmentation segmentAir(const volumes::Volume& volume, const SegmentationSettings& settings);

/// Throws ColonError naming what was found when no region is colon (no air at all, air only
/// outside the body, only small or round pockets, lungs).
void requireColon(const AirSegmentation& segmentation, const SegmentationSettings& settings);

}  // namespace colon
