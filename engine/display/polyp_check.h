/// @brief The polyp-shape regression check: each polyp of a ground truth seen from poses along
/// the path at several elevations toward the Immersive Cabin's missing ceiling, through the
/// conformal map, the linear baseline and no map, for both eyes, against a pinhole reference
/// aimed at the polyp from the same eye; shape measured as the viewer sees it
/// (colon/polyp_shape.h), never in wall pixels.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "colon/polyp_shape.h"
#include "colon/polyp_truth.h"
#include "conformal/cube_map.h"
#include "engine/display/camera_path.h"
#include "engine/display/display.h"
#include "engine/render/raycaster.h"

namespace engine {

/// Where the polyp is put in the view: its direction from the map centre at `elevationDeg`
/// above the horizon and `azimuthDeg` to the right of straight ahead.
struct PolypPose {
    std::string name;
    double elevationDeg = 0.0;
    double azimuthDeg = 0.0;
    bool isTargeted = true;  ///< counted against the targets (the corner pose is only reported)
};

/// For the 5-wall cabin (its ceiling's edge straight ahead is 36.8 degrees up, its corners 27.9
/// degrees up at 45 degrees azimuth) and a polyp of about 5 degrees angular radius: "wall" 15
/// degrees up on the front wall; "edge" 28, the polyp's top near the ceiling's edge;
/// "ceiling_44" and "ceiling_50" on the ceiling's directions, where the conformal map puts the
/// polyp's image at least 10 degrees from the display's singular points (the missing ceiling's
/// corners, where the slit ends, and its edge midpoints, the images of the zenith where the
/// slit's arcs meet); reported but not targeted: "ceiling_60", whose image lies 6 degrees from
/// the front edge's midpoint, and "corner", 33 degrees up at 45 degrees azimuth, 5 degrees from a
/// ceiling corner. Each result records its image's distance to the singular points.
std::vector<PolypPose> defaultPolypPoses();

struct PolypCheckJob {
    Display display;  ///< its map is replaced by each map under test
    std::vector<conformal::MapKind> maps{conformal::MapKind::Conformal, conformal::MapKind::Linear,
                                         conformal::MapKind::None};
    std::vector<colon::PolypSurface> polyps;  ///< the ground truth
    std::vector<int> polypIndices;            ///< which of them to check
    Centreline centreline;
    PathSettings path;
    std::vector<PolypPose> poses = defaultPolypPoses();
    /// The polyp's angular radius from the eye, which sets how far back along the path the eye
    /// is placed: a conformal map keeps shapes in the small, so the polyp must be small enough in
    /// the view to stay clear of the map's singular points.
    double angularRadiusDeg = 5.0;
    double mmPerMetre = 10.0;
    RenderSettings settings;  ///< hits are turned on
    WarpMode warpMode = WarpMode::Chord;
    int referenceSize = 256;  ///< the pinhole reference's side, pixels
    double toleranceMm = 0.25;
    int cropSize = 160;
};

/// One polyp at one pose for one eye through one map.
struct PolypViewResult {
    int polyp = 0;
    double diameterMm = 0.0;
    std::string pose;
    bool isTargeted = true;
    bool isOnCeiling = false;  ///< its direction from the map centre falls on the missing ceiling
    Eye eye = Eye::Left;
    conformal::MapKind map = conformal::MapKind::Conformal;
    CameraPose cameraPose;
    double angularRadiusDeg = 0.0;  ///< the polyp's angular radius from the eye at this pose
    /// The angle from the polyp's image (its mean display direction, from the map centre) to
    /// the nearest of the display's singular points: the missing wall's corners, where the slit
    /// ends, and its edges' midpoints, where the map sends the slit's meeting point.
    double singularDistanceDeg = 0.0;
    colon::ShapeMeasures view, reference;
    double visibleFraction = 1.0;  ///< no map: the share of the reference's area the view shows
    bool isVisible = false;        ///< enough pixels (colon::kMinPolypPixels), and 95 % of it shown
    double aspectError = 0.0;      ///< |view - reference| / reference
    double circularityError = 0.0;
    double gridAngleErrorDeg = 0.0;
    colon::RgbaImage crop;           ///< the view in its tangent plane around the polyp
    colon::RgbaImage referenceCrop;  ///< the reference's, at the same relative scale
};

/// The cube map each bending map under test needs, by kind: the caller bakes or loads them.
using CubeMapLookup = std::function<const conformal::CubeMap&(conformal::MapKind)>;

/// Renders and measures every polyp x pose x eye x map of `job`. For each polyp the eye is placed
/// on its path segment where the polyp subtends job.angularRadiusDeg (before it, antegrade,
/// where the path allows), the same point for every pose: only the display direction changes,
/// so each pose isolates what the map does there. The view is turned about the eye to put the
/// polyp at the pose's elevation and azimuth, forward as close to the path's as that allows. `onProgress(done, total)`
/// counts rendered frames (one per polyp, pose and map, both eyes together). Throws
/// std::invalid_argument for a polyp index the truth lacks or a display without a ceiling gap.
std::vector<PolypViewResult> checkPolyps(Raycaster& raycaster, const PolypCheckJob& job, const CubeMapLookup& cubeMaps,
                                         const std::function<void(int, int)>& onProgress = {});

/// The pose at `base`'s position turned so that `pointMm` lies at `elevationDeg` above the
/// horizon and `azimuthDeg` to the right of straight ahead, as close to `base`'s view as that
/// allows. Throws std::invalid_argument when the point is at the position.
CameraPose poseSeeing(const CameraPose& base, const glm::dvec3& pointMm, double elevationDeg, double azimuthDeg);

}  // namespace engine
