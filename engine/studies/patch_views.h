/// @brief Views of the wall a fly-through never showed: for an unseen patch of
/// colon/surface_coverage.h, the pose from which it is best seen (searched among the frames
/// near it and points of the lumen in front of it) and its picture with the unseen wall tinted.
#pragma once

#include <vector>

#include "colon/surface_coverage.h"
#include "engine/render/raycaster.h"
#include "engine/review/review_sheet.h"
#include "engine/sequence/camera_path.h"
#include "volumes/volume.h"

namespace engine {

/// A patch with the pose that shows most of it.
struct PatchView {
    colon::UnseenPatch patch;
    CameraPose pose;
    int nearestFrame = -1;     ///< the index in the poses given of the frame nearest the pose
    double shownPercent = 0.0; ///< of the patch's area, hit by the pose's view
    std::string picture;       ///< where the caller wrote its picture; empty until then
};

/// The pinhole view from `pose` toward `lookAtMm`, 90 degrees across, `pixels` square, with hits.
RenderedImage patchView(Raycaster& raycaster, const CameraPose& pose, const glm::dvec3& lookAtMm,
                        const RenderSettings& settings, int pixels);

/// For each of the first `count` patches (largest first), the pose that shows most of it.
/// Candidates: the six frames of `poses` nearest the patch, each turned to look straight at it,
/// and the points of the lumen (below the iso value in `volume`) 4, 8 and 12 mm in front of it
/// along its normal (a virtual camera steered off the path, as a reader would to look behind a
/// fold); the one whose view hits the most patch area (elements within `snapMm` of a hit) wins.
std::vector<PatchView> locatePatches(Raycaster& raycaster, const colon::SurfaceCoverage& coverage,
                                     const std::vector<colon::UnseenPatch>& patches,
                                     const std::vector<CameraPose>& poses, const volumes::Volume& volume,
                                     const RenderSettings& settings, double snapMm, int count);

/// `image` (rendered with hits) with the wall that `coverage` never saw tinted red.
RgbaImage tintedUnseen(RenderedImage image, const colon::SurfaceCoverage& coverage, double snapMm);

}  // namespace engine
