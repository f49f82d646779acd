/// @brief The polyp-shape regression check: each polyp of a ground truth seen from poses that
/// put it on a display's walls, near and on its missing walls' directions and toward a slit tip
/// (polyp_poses.h), for the left, centre and right eyes, through the conformal map, the linear
/// baseline and no map, against a pinhole reference aimed at the polyp from the same eye; shape
/// measured as the viewer sees it (colon/polyp_shape.h), never in wall pixels; and beside each
/// result what the map alone predicts there (colon/polyp_shape_prediction.h), which also sets
/// how far from each polyp the eye stands and which poses are held to the targets.
#pragma once

#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "colon/polyp_shape.h"
#include "colon/polyp_truth.h"
#include "conformal/cube_map.h"
#include "engine/display/display.h"
#include "engine/render/raycaster.h"
#include "engine/sequence/camera_path.h"
#include "engine/studies/polyp_poses.h"

namespace engine {

struct PolypCheckJob {
    Display display;  ///< its map is replaced by each map under test
    std::vector<conformal::MapKind> maps{conformal::MapKind::Conformal, conformal::MapKind::Linear,
                                         conformal::MapKind::None};
    std::vector<colon::PolypSurface> polyps;  ///< the ground truth
    std::vector<int> polypIndices;            ///< which of them to check
    Centreline centreline;
    PathSettings path;
    std::vector<PolypPose> poses;  ///< empty: polypPosesFor(display)
    /// The polyp's angular radius from the eye, at most. A conformal map keeps shapes in the
    /// small; over the polyp's extent its scale changes, so each polyp's eye stands as close as
    /// this, or farther back until the map's predicted error for the polyp's own outline stays
    /// within predictedTarget at every targetable pose (checkPolyps).
    double angularRadiusDeg = 5.0;
    /// The least angular radius the eye's place may give: a pose whose predicted error exceeds
    /// predictedTarget even here is reported with that floor, not targeted.
    double minAngularRadiusDeg = 3.0;
    double predictedTarget = 0.02;  ///< the map's predicted aspect and circularity error, at most
    double mmPerMetre = 10.0;
    RenderSettings settings;  ///< hits are turned on
    WarpMode warpMode = WarpMode::EyeCentred;
    int referenceSize = 256;  ///< the pinhole reference's side, pixels
    double toleranceMm = 0.25;
    int cropSize = 160;
    /// Only the walls that the polyp's image (by the prediction, with a margin) can reach are
    /// rendered; true renders every wall (a test compares the two).
    bool isRenderingEveryWall = false;
    /// A stereo eye whose error differs from the prediction by more than a point is rendered
    /// again through the exact warp, to tell the warp's share from the eye's.
    bool isRenderingExactWhereApart = true;
};

/// What the map alone gives a polyp at a pose (colon::predictPolypShape); NaN where the map shows
/// no direction at the polyp's centre (it lies on the slit, or on a missing wall without a map).
struct PredictedErrors {
    bool isFound = false;
    double aspectError = std::numeric_limits<double>::quiet_NaN();
    double circularityError = std::numeric_limits<double>::quiet_NaN();
    double gridAngleErrorDeg = std::numeric_limits<double>::quiet_NaN();
};

/// A pose as the check holds it: whether its results are held to the targets, by the
/// conformal map's prediction at the least angular radius (the floor).
struct PoseTarget {
    PolypPose pose;
    bool isTargeted = false;
    PredictedErrors floor;  ///< at PolypCheckJob::minAngularRadiusDeg
};

/// The poses with their targets (targetable where a circle's prediction at the least radius meets
/// the target), the angular radius at which a round polyp would stand (the largest up to
/// angularRadiusDeg whose circle prediction meets the target at every targetable pose; each
/// polyp's own place comes from the predictions for its outline and for a circle, checkPolyps),
/// and the largest one a polyp hidden at every distance from there may come closer to (10
/// degrees more); a polyp is held to the targets only at the poses whose predictions for its
/// outline and for a circle of its angular radius from its place meet them, and only where some
/// place on its path shows it in full view.
struct PolypCheckPlan {
    std::vector<PoseTarget> poses;
    double angularRadiusDeg = 5.0;
    double widestAngularRadiusDeg = 5.0;
};

/// One polyp at one pose for one eye through one map.
struct PolypViewResult {
    int polyp = 0;
    double diameterMm = 0.0;
    std::string pose;
    bool isTargeted = true;
    /// Why not, where not: "pose" (the pose's floor exceeds the target), "not in view" (no place
    /// on the polyp's path shows it in full view), "prediction" (the conformal map's prediction
    /// from the polyp's place, for its outline or for a circle of its angular radius, exceeds the
    /// target: the circle's only where the eye came closer to see past a fold or a bend).
    std::string untargetedBecause;
    std::string missingWall;  ///< the missing wall its direction falls on; empty: a present one
    Eye eye = Eye::Left;
    conformal::MapKind map = conformal::MapKind::Conformal;
    WarpMode warp = WarpMode::Polyline;  ///< how this eye's rays were bent (none without a map)
    CameraPose cameraPose;
    double angularRadiusDeg = 0.0;  ///< the polyp's angular radius from the eye at this pose
    /// The angle from the polyp's image (its mean display direction, from the map centre) to
    /// the nearest of the display's singular points (singularDirectionsOf).
    double singularDistanceDeg = 0.0;
    colon::ShapeMeasures view, reference;
    /// The reference's polyp pixels against those the polyp's own outline would cover with
    /// nothing in the way: below 0.9 a fold or a bend hides part of it (occluded).
    double referenceUnoccludedShare = 0.0;
    /// The share of those that something in front of the polyp hides in the reference (a fold's
    /// edge, a bend of the wall; colon::isHiddenInFront): above half a percent it counts as occluded.
    double referenceHiddenInFrontShare = 0.0;
    double visibleFraction = 1.0;  ///< no map: the share of the reference's area the view shows
    bool isVisible = false;        ///< enough pixels (colon::kMinPolypPixels), and 95 % of it shown
    double aspectError = 0.0;      ///< |view - reference| / reference
    double circularityError = 0.0;
    double gridAngleErrorDeg = 0.0;
    /// The error budget: what the map predicts for the polyp's own outline seen from its place
    /// (its ground truth's surface, nothing rendered), for a circle of its angular radius (the
    /// same for every polyp at a pose), and for a circle at the least angular radius (the floor);
    /// the centre eye's aspect error at the same pose and map; for a stereo eye that was rendered
    /// again, its aspect error through the exact warp; and, where the aspect error is more than
    /// a point from the prediction, the term responsible: "warp" (this warp against the exact
    /// one), "eye" (the stereo eye against the centre), "occlusion" (a fold or a bend hides part
    /// of the polyp: referenceUnoccludedShare below 0.9, or referenceHiddenInFrontShare above
    /// 0.005), "pixels" (the view's narrow axis is under 25 pixels), or "outline" (the rest: the outline the rendered polyp shows is not the
    /// ground truth's the prediction takes, as where a flat polyp's rim merges into a fold; twice
    /// the wall resolution leaves such a result where it was).
    PredictedErrors predicted, predictedCircle, predictedFloor;
    double centreAspectError = std::numeric_limits<double>::quiet_NaN();
    double exactWarpAspectError = std::numeric_limits<double>::quiet_NaN();
    std::string apartBecause;
    colon::RgbaImage crop;           ///< the view in its tangent plane around the polyp
    colon::RgbaImage referenceCrop;  ///< the reference's, at the same relative scale
};

/// The cube map each bending map under test needs, by kind: the caller bakes or loads them.
using CubeMapLookup = std::function<const conformal::CubeMap&(conformal::MapKind)>;

/// The poses (job.poses, or the display's own), their targets and the angular radius, from the
/// conformal map's prediction alone. Throws std::invalid_argument for a display without a
/// missing wall or a radius range outside (0, 30] degrees.
PolypCheckPlan planPolypCheck(const PolypCheckJob& job, const CubeMapLookup& cubeMaps);

/// Renders and measures every polyp x pose x eye x map of `job` by `plan`. For each polyp the eye
/// is placed on its path segment where the map's predictions allow (from angularRadiusDeg down
/// to minAngularRadiusDeg, closer past a fold; before the polyp, antegrade, where the path
/// allows), the same point for every pose: only the display direction changes, so each pose
/// isolates what the map does there. The view is turned about the eye to
/// put the polyp along the pose's direction, forward as close to the path's as that allows.
/// `onProgress(done, total)` counts rendered frames (one per polyp, pose and map, the three
/// eyes together). Throws std::invalid_argument for a polyp index the truth lacks.
std::vector<PolypViewResult> checkPolyps(Raycaster& raycaster, const PolypCheckJob& job, const PolypCheckPlan& plan,
                                         const CubeMapLookup& cubeMaps,
                                         const std::function<void(int, int)>& onProgress = {});

}  // namespace engine
