/// @brief Electronic cleansing: residual fluid tagged with oral contrast lies in the colon's
/// lowest parts under a flat level; it is relabelled as lumen and its HU replaced, so that the
/// iso surface shows the colon wall beneath it instead of a flat fluid surface.
///
/// A pool is a 6-connected region of tagged voxels (HU above taggedHu) whose upper surface
/// meets the colon's air: most of its topmost voxels (those with no tagged voxel above them,
/// "above" against gravity, from the scan's orientation) have colon air within levelGapMm above
/// them, the thin partial-volume layer of the air-fluid level between. Bone, which is also above
/// +200 HU, meets soft tissue on top, not air, and fails that test; a region larger than
/// maxPoolMl is not residual fluid and is left as it is.
///
/// Partial volume, as a two-material mix at each boundary:
///  - fluid-wall: a voxel of value h between tissue and fluid holds a fluid fraction
///    f = (h - tissueHu) / (fluidHu - tissueHu); it becomes tissue + f (airHu - tissue), the
///    same fraction of air, so the wall's edge keeps its place and its ramp;
///  - air-fluid level: a voxel between air above and fluid below is lumen either way: air.
/// Where air, fluid and wall meet in one voxel the two-material mix is an approximation.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "colon/lumen_segmentation.h"
#include "volumes/volume.h"

namespace colon {

struct CleansingSettings {
    double taggedHu = 200.0;     ///< oral contrast tags fluid well above soft tissue
    double tissueHu = 40.0;      ///< the colon wall's value for the partial-volume mix
    double airHu = -1000.0;      ///< what cleansed fluid becomes
    double levelGapMm = 3.0;     ///< the air-fluid level's partial-volume layer is at most this thick
    double minSurfaceContact = 0.5;  ///< share of a pool's top surface that must meet colon air
    double maxPoolMl = 1000.0;
    double minPoolMl = 0.05;
};

struct CleansingReport {
    int pools = 0;
    std::size_t fluidVoxels = 0;  ///< tagged voxels relabelled as lumen
    std::size_t edgeVoxels = 0;   ///< boundary voxels whose HU was unmixed
    double fluidMl = 0.0;
    int rejectedRegions = 0;  ///< tagged regions touching the colon that were not pools (bone, too large)
};

/// Finds the pools under the colon air (the voxels of `air` whose region is of kind Colon),
/// rewrites their HU in `volume` as described above, and returns a mask of the voxels that
/// became lumen (1), the colon air itself not included.
std::vector<uint8_t> cleanseTaggedFluid(volumes::Volume& volume, const AirSegmentation& air,
                                        const CleansingSettings& settings, CleansingReport& report);

}  // namespace colon
