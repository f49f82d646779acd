#include "engine/studies/polyp_check.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <stdexcept>
#include <span>
#include <tuple>

#include "colon/polyp_shape_prediction.h"
#include "conformal/cave_box.h"
#include "engine/render/pinhole_camera.h"
#include "engine/sequence/frame_sequence.h"
#include "engine/studies/view_samples.h"

namespace engine {
namespace {

constexpr std::array<Eye, 3> kEyes{Eye::Left, Eye::Centre, Eye::Right};
constexpr double kPi = 3.14159265358979323846;

/// F of a map for the prediction, in CAVE axes: the cube map's scene direction for a displayed
/// direction (bilinear, as the ray caster reads it), nothing for a missing one; without a map
/// (`cube` null) the displayed directions themselves.
colon::SceneFromDisplay sceneFromDisplayOf(const conformal::CaveBox& box, const conformal::CubeMap* cube) {
    return [box, cube](const glm::dvec3& display) -> glm::dvec3 {
        if (conformal::isMissingDirection(box, display)) return glm::dvec3(0.0);
        if (!cube) return display;
        return glm::dvec3(conformal::sampleCubeMapBilinear(*cube, display));
    };
}

PredictedErrors errorsOf(const colon::PredictedShape& shape) {
    PredictedErrors errors;
    errors.isFound = shape.isFound && shape.view.pixels >= 3;
    if (errors.isFound) {
        errors.aspectError = shape.aspectError;
        errors.circularityError = shape.circularityError;
        errors.gridAngleErrorDeg = shape.gridAngleErrorDeg;
    }
    return errors;
}

/// The predictions of one job: a circle's, each made once (by map, pose and angular radius), and
/// a polyp's own outline seen from the map centre at a camera pose.
class Predictions {
public:
    Predictions(const PolypCheckJob& job, const CubeMapLookup& cubeMaps)
        : mBox(caveBoxOf(job.display)), mMmPerMetre(job.mmPerMetre), mCubeMaps(cubeMaps) {}

    colon::PredictedShape ofOutline(conformal::MapKind map, const colon::PolypSurface& polyp, const CameraPose& pose) const {
        // The polyp in CAVE axes about the map centre, which the pose puts at its position.
        const glm::dmat3 toCave =
            glm::transpose(caveToVolumeRotation(ScenePose{pose.positionMm, pose.forward, pose.up, mMmPerMetre}));
        colon::PolypSurface inCave = polyp;
        inCave.centreMm = toCave * (polyp.centreMm - pose.positionMm);
        inCave.baseMm = toCave * (polyp.baseMm - pose.positionMm);
        inCave.baseNormal = toCave * polyp.baseNormal;
        const conformal::CubeMap* cube = map == conformal::MapKind::None ? nullptr : &mCubeMaps(map);
        return colon::predictPolypShape(sceneFromDisplayOf(mBox, cube), inCave);
    }

    const colon::PredictedShape& at(conformal::MapKind map, const PolypPose& pose, double radiusDeg) {
        const glm::dvec3& d = pose.directionCave;
        const auto key = std::make_tuple(static_cast<int>(map), std::llround(d.x * 1e12), std::llround(d.y * 1e12),
                                         std::llround(d.z * 1e12), std::lround(radiusDeg * 1000.0));
        auto found = mShapes.find(key);
        if (found == mShapes.end()) {
            const conformal::CubeMap* cube = map == conformal::MapKind::None ? nullptr : &mCubeMaps(map);
            found = mShapes.emplace(key, colon::predictPolypShape(sceneFromDisplayOf(mBox, cube), pose.directionCave,
                                                                  glm::radians(radiusDeg))).first;
        }
        return found->second;
    }

private:
    conformal::CaveBox mBox;
    double mMmPerMetre;
    const CubeMapLookup& mCubeMaps;
    std::map<std::tuple<int, long long, long long, long long, long>, colon::PredictedShape> mShapes;
};

/// The larger of the predicted aspect and circularity errors; infinite where the map shows no
/// direction at the polyp's centre.
double worstPredicted(const PredictedErrors& errors) {
    if (!errors.isFound) return std::numeric_limits<double>::infinity();
    return std::max(errors.aspectError, errors.circularityError);
}

/// Why a result is not held to the targets; empty where it is. The pose is not targetable (its
/// floor exceeds the target); no place on the polyp's path shows it in full view; or the
/// conformal map's prediction from the polyp's place exceeds the target: for its own outline, or
/// for a circle of its angular radius (over the target only where the eye came closer than the
/// plan's radius to see past a fold or a bend). The outline's prediction can be the smaller where
/// the outline's own elongation and the map's stretch cross, but the outline a rendered polyp
/// shows is never exactly the truth's, so the circle's bound must hold too.
std::string untargetedBecauseOf(const PoseTarget& target, bool isInFullView, const PredictedErrors& outline,
                                const PredictedErrors& circle, double predictedTarget) {
    if (!target.isTargeted) return "pose";
    if (!isInFullView) return "not in view";
    if (worstPredicted(outline) > predictedTarget || worstPredicted(circle) > predictedTarget) return "prediction";
    return "";
}

struct Reference {
    colon::ShapeMeasures measures;
    colon::RgbaImage crop;
    glm::dvec3 gridNormal{0.0};  ///< the line of sight the painted grid faces
    int unoccludedPixels = 0;    ///< the polyp's pixels were nothing else in the way (polypOutlineOf)
    int hiddenInFrontPixels = 0; ///< of those, the ones something in front of the polyp hides
};

/// The pixels of a view that would show the polyp with nothing else in the way (those whose ray
/// meets its own surface: its sphere, for a sessile or flat polyp above the wall plane), and of
/// those the ones whose rendered first hit lies well before that surface (colon::isHiddenInFront:
/// a fold or a bend of the wall in front of it, not the rim where it rounds off into the wall).
struct PolypOutline {
    int unoccludedPixels = 0;
    int hiddenInFrontPixels = 0;
};

PolypOutline polypOutlineOf(const ViewRays& rays, const std::vector<colon::ViewSample>& samples,
                            const colon::PolypSurface& polyp, double toleranceMm) {
    PolypOutline outline;
    glm::dvec3 hit;
    for (int row = 0; row < rays.height; ++row) {
        for (int column = 0; column < rays.width; ++column) {
            const glm::dvec3 direction = rayDirectionOf(rays, column, row);
            if (!colon::firstPolypHit(polyp, rays.eyeMm, direction, hit)) continue;
            ++outline.unoccludedPixels;
            const colon::ViewSample& sample = samples[static_cast<std::size_t>(row) * static_cast<std::size_t>(rays.width) +
                                                      static_cast<std::size_t>(column)];
            if (sample.isHit && colon::isHiddenInFront(polyp, rays.eyeMm, direction, sample.hitMm, toleranceMm)) {
                ++outline.hiddenInFrontPixels;
            }
        }
    }
    return outline;
}

/// The tangent-plane half-width of a view's crop: the polyp at the same relative size in each.
double cropHalfWidth(const colon::ShapeMeasures& measures) { return 1.8 * std::sqrt(measures.areaSr / kPi); }

/// Whether a reference also makes its crop: not while searching for the eye's place, where only
/// the polyp's pixels count.
enum class CropChoice { Make, Skip };

/// The pinhole reference from `eye`'s position at `scene`, aimed at the polyp, framing it.
Reference renderReference(Raycaster& raycaster, const PolypCheckJob& job, const colon::PolypSurface& polyp,
                          const ScenePose& scene, Eye eye, const RenderSettings& settings, CropChoice crop) {
    const glm::dvec3 eyeMm = wallView(job.display, WallName::Front, eye, scene, WarpMode::None).rays.eyeMm;
    const glm::dvec3 aim = colon::polypAimPointOf(polyp);
    const double distance = glm::length(aim - eyeMm);
    const double angularRadius = std::asin(std::min(1.0, (0.5 * polyp.diameterMm + 1.0) / distance));
    PinholeCamera camera;
    camera.positionMm = eyeMm;
    camera.lookAtMm = aim;
    camera.up = scene.up;
    camera.verticalFovDeg = std::clamp(glm::degrees(3.0 * angularRadius), 5.0, 150.0);
    camera.width = camera.height = job.referenceSize;
    const ViewRays rays = viewRaysFrom(camera);
    const RenderedImage image = raycaster.render(rays, settings);
    const std::vector<colon::ViewSample> samples = viewSamples(rays, image);
    Reference reference;
    const PolypOutline outline = polypOutlineOf(rays, samples, polyp, job.toleranceMm);
    reference.unoccludedPixels = outline.unoccludedPixels;
    reference.hiddenInFrontPixels = outline.hiddenInFrontPixels;
    reference.gridNormal = glm::normalize(aim - eyeMm);
    reference.measures = colon::measurePolypShape(samples, polyp, job.toleranceMm, reference.gridNormal);
    if (crop == CropChoice::Make && reference.measures.pixels >= 3) {
        const glm::dvec3 right = caveToVolumeRotation(scene)[0];
        reference.crop = colon::tangentPlaneCrop(samples, reference.measures.centreDirection, right,
                                                 cropHalfWidth(reference.measures), job.cropSize);
    }
    return reference;
}

/// A polyp is in full view where the reference shows at least this share of the pixels its own
/// outline would cover with nothing in the way (the rim's rounding into the wall takes up to a
/// tenth)...
constexpr double kFullViewShare = 0.9;

/// ... and something in front of it (a fold's edge, a bend of the wall) hides at most this share
/// of them. The prediction takes the whole outline; a straight edge across it changes the
/// outline's own aspect by about twice the share it hides (a disc cut by a chord: 0.47 % hidden,
/// aspect 0.9 % off; 1.9 %, 3.4 %; 5.2 %, 9 %), and the map then bends that edge with the rest,
/// so past half a percent the visible shape is no longer the one predicted within the budget's
/// point.
constexpr double kMostHiddenInFront = 0.005;

/// The share of the polyp's own outline that something in front of it hides in `reference`.
double hiddenInFrontShare(const Reference& reference) {
    return reference.unoccludedPixels > 0
               ? static_cast<double>(reference.hiddenInFrontPixels) / reference.unoccludedPixels
               : 0.0;
}

/// Whether the polyp is in full view from the centre eye at `pose` (kFullViewShare, kMostHiddenInFront).
bool isInFullView(Raycaster& raycaster, const PolypCheckJob& job, const colon::PolypSurface& polyp,
                  const CameraPose& pose, const RenderSettings& settings) {
    const ScenePose scene{pose.positionMm, pose.forward, pose.up, job.mmPerMetre};
    const Reference reference = renderReference(raycaster, job, polyp, scene, Eye::Centre, settings, CropChoice::Skip);
    return reference.unoccludedPixels >= colon::kMinPolypPixels &&
           reference.measures.pixels >= kFullViewShare * reference.unoccludedPixels &&
           hiddenInFrontShare(reference) <= kMostHiddenInFront;
}

/// Poses tried at one distance.
constexpr int kCandidates = 12;

/// The worst of the conformal map's predicted errors for `polyp` seen from `base`, where it
/// subtends `radiusDeg`, over the plan's targetable poses (PoseTarget::isTargeted, the poses
/// rendered): for its own outline and for a circle of that radius, the two a result is targeted
/// by (untargetedBecauseOf).
double worstPredictionFrom(Predictions& predictions, const PolypCheckPlan& plan, const colon::PolypSurface& polyp,
                           const CameraPose& base, double radiusDeg) {
    double worst = 0.0;
    for (const PoseTarget& target : plan.poses) {
        if (!target.isTargeted) continue;
        const PredictedErrors circle = errorsOf(predictions.at(conformal::MapKind::Conformal, target.pose, radiusDeg));
        const CameraPose pose = poseSeeing(base, colon::polypAimPointOf(polyp), target.pose.directionCave);
        const PredictedErrors outline = errorsOf(predictions.ofOutline(conformal::MapKind::Conformal, polyp, pose));
        worst = std::max({worst, worstPredicted(circle), worstPredicted(outline)});
    }
    return worst;
}

/// Where a polyp's eyes stand: the pose, the polyp's angular radius from there, and whether the
/// polyp is in full view from it (kFullViewShare).
struct EyePlace {
    CameraPose pose;
    double angularRadiusDeg = 0.0;
    bool isInFullView = false;
};

/// The eye's place for `polyp`: on its path segment, the first pose within 10 % of the distance
/// at which the polyp subtends a radius (those before the polyp, antegrade, first) that has the
/// polyp in full view. The radius goes down from job.angularRadiusDeg in quarter degrees to
/// job.minAngularRadiusDeg until the conformal map's predictions from there (for the polyp's own
/// outline and for a circle of that radius) meet the target at every targetable pose; where none
/// does, the place in view with the least prediction. Where a fold or a bend hides the polyp at
/// all those distances it comes closer, a degree at a time, up to plan.widestAngularRadiusDeg;
/// failing that, the pose nearest job.angularRadiusDeg's distance, not in full view (its results
/// are reported, not targeted).
EyePlace eyePlaceFor(Raycaster& raycaster, const PolypCheckJob& job, const PolypCheckPlan& plan,
                     Predictions& predictions, const colon::PolypSurface& polyp, const RenderSettings& settings) {
    PathSettings fine = job.path;
    fine.stepMm = 0.5;
    const glm::dvec3 aim = colon::polypAimPointOf(polyp);
    const std::vector<CameraPose> poses = posesAlong(nearestSegment(job.centreline, aim), fine);
    const auto distanceTo = [&](const CameraPose& pose) { return glm::length(pose.positionMm - aim); };
    const auto nearest = static_cast<std::size_t>(
        std::min_element(poses.begin(), poses.end(),
                         [&](const CameraPose& a, const CameraPose& b) { return distanceTo(a) < distanceTo(b); }) -
        poses.begin());
    const auto placeInView = [&](double radius) -> std::optional<CameraPose> {
        const double wanted = 0.5 * polyp.diameterMm / std::sin(glm::radians(radius));
        std::vector<std::size_t> order(poses.size());
        for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
        const auto mismatch = [&](std::size_t i) { return std::abs(distanceTo(poses[i]) - wanted) / wanted; };
        std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
            // Within 10 % of the distance, a pose before the polyp wins; beyond, the nearer distance.
            const double ma = std::max(mismatch(a), 0.1), mb = std::max(mismatch(b), 0.1);
            if (ma != mb) return ma < mb;
            return a <= nearest && b > nearest;
        });
        int tried = 0;
        for (std::size_t i : order) {
            if (mismatch(i) > 0.1 || tried >= kCandidates) break;
            if (i % 2 == 1) continue;  // candidates 1 mm apart: neighbours 0.5 mm apart see the same
            ++tried;
            if (isInFullView(raycaster, job, polyp, poses[i], settings)) return poses[i];
        }
        return std::nullopt;
    };
    std::optional<EyePlace> best;
    double bestWorst = std::numeric_limits<double>::infinity();
    for (double radius = job.angularRadiusDeg; radius >= job.minAngularRadiusDeg - 1e-9; radius -= 0.25) {
        const std::optional<CameraPose> place = placeInView(radius);
        if (!place) continue;
        const double worst = worstPredictionFrom(predictions, plan, polyp, *place, radius);
        if (worst < bestWorst) {
            best = EyePlace{*place, radius, true};
            bestWorst = worst;
        }
        if (worst <= job.predictedTarget) return *best;
    }
    if (best) return *best;
    for (double radius = job.angularRadiusDeg + 1.0; radius <= plan.widestAngularRadiusDeg + 1e-9; radius += 1.0) {
        if (const std::optional<CameraPose> place = placeInView(radius)) return EyePlace{*place, radius, true};
    }
    const double wanted = 0.5 * polyp.diameterMm / std::sin(glm::radians(job.angularRadiusDeg));
    const auto nearerToWanted = [&](const CameraPose& a, const CameraPose& b) {
        return std::abs(distanceTo(a) - wanted) < std::abs(distanceTo(b) - wanted);
    };
    const CameraPose nearestToWanted = *std::min_element(poses.begin(), poses.end(), nearerToWanted);
    return EyePlace{nearestToWanted, job.angularRadiusDeg, false};
}

/// The smallest angle between the ray from the map centre along `axis` (CAVE axes) and the
/// directions of the wall's points.
double angleToWall(const Display& display, WallName wall, const glm::dvec3& axis) {
    const WallRectangle rect = wallRectangle(display, wall);
    const glm::dvec3 origin = rect.topLeftM - display.mapCentreM;
    const glm::dvec3 normal = glm::cross(rect.widthM, rect.heightM);
    const double along = glm::dot(axis, normal);
    if (std::abs(along) > 1e-12) {
        const double t = glm::dot(origin, normal) / along;
        if (t > 0.0) {
            const glm::dvec3 onPlane = t * axis - origin;
            const double u = glm::dot(onPlane, rect.widthM) / glm::dot(rect.widthM, rect.widthM);
            const double v = glm::dot(onPlane, rect.heightM) / glm::dot(rect.heightM, rect.heightM);
            if (u >= 0.0 && u <= 1.0 && v >= 0.0 && v <= 1.0) return 0.0;
        }
    }
    // Not through the wall: the nearest direction lies on its edges.
    constexpr int kEdgeSamples = 256;
    double nearest = kPi;
    const std::array<std::pair<glm::dvec3, glm::dvec3>, 4> edges{
        {{origin, rect.widthM}, {origin, rect.heightM}, {origin + rect.heightM, rect.widthM}, {origin + rect.widthM, rect.heightM}}};
    for (const auto& [start, span] : edges) {
        for (int i = 0; i <= kEdgeSamples; ++i) {
            const glm::dvec3 point = glm::normalize(start + (static_cast<double>(i) / kEdgeSamples) * span);
            nearest = std::min(nearest, std::acos(std::clamp(glm::dot(point, axis), -1.0, 1.0)));
        }
    }
    return nearest;
}

/// The walls whose directions come within `coneRad` of `axis` (CAVE axes), in the display's order.
std::vector<WallName> wallsNear(const Display& display, const glm::dvec3& axis, double coneRad) {
    std::vector<WallName> walls;
    for (const DisplayWall& wall : display.walls) {
        if (angleToWall(display, wall.name, glm::normalize(axis)) <= coneRad) walls.push_back(wall.name);
    }
    return walls;
}

/// The walls a view of the polyp needs: those its image (the prediction's, from the map centre)
/// can reach, with room for the crop around it and the eyes' offset; every wall where the
/// prediction found no image.
std::vector<WallName> wallsToRender(const PolypCheckJob& job, const colon::PredictedShape& prediction,
                                    const glm::dvec3& sceneDirectionCave, double angularRadiusRad, bool hasMap) {
    std::vector<WallName> every;
    for (const DisplayWall& wall : job.display.walls) every.push_back(wall.name);
    if (job.isRenderingEveryWall) return every;
    const glm::dvec3 axis = hasMap ? prediction.displayDirection : sceneDirectionCave;
    const double radius = hasMap ? prediction.displayRadiusRad : angularRadiusRad;
    if (hasMap && !prediction.isFound) return every;
    return wallsNear(job.display, axis, 2.5 * radius + glm::radians(4.0));
}

/// `walls` of the display seen by each of `eyes`, rendered in one submission.
std::vector<WallImage> renderSomeWalls(Raycaster& raycaster, const Display& display, const std::vector<WallName>& walls,
                                       const ScenePose& scene, std::span<const Eye> eyes,
                                       const RenderSettings& settings, WarpMode warpMode) {
    std::vector<RenderRequest> requests;
    std::vector<std::pair<Eye, WallName>> labels;
    for (Eye eye : eyes) {
        for (WallName wall : walls) {
            const WallView view = wallView(display, wall, eye, scene, warpMode);
            requests.push_back({view.rays, settings, view.warp});
            labels.emplace_back(eye, wall);
        }
    }
    RenderBatch batch = raycaster.submit(requests);
    std::vector<RenderedImage> images = raycaster.collect(batch);
    std::vector<WallImage> out;
    for (std::size_t i = 0; i < images.size(); ++i) out.push_back({labels[i].first, labels[i].second, std::move(images[i])});
    return out;
}

/// The samples of one eye's walls.
void samplesOfEye(const std::vector<WallImage>& walls, const Display& display, const ScenePose& scene, Eye eye,
                  WarpMode warpMode, std::vector<colon::ViewSample>& samples) {
    samples.clear();
    for (const WallImage& wall : walls) {
        if (wall.eye != eye) continue;
        appendViewSamples(wallView(display, wall.wall, eye, scene, warpMode).rays, wall.image, samples);
    }
}

double relativeError(double value, double reference) {
    return reference != 0.0 ? std::abs(value - reference) / std::abs(reference) : std::numeric_limits<double>::quiet_NaN();
}

/// The polyp's image across its narrow axis, pixels.
double narrowAxisPixels(const colon::ShapeMeasures& view) {
    return view.aspect > 0.0 ? view.pixelsAcross / std::sqrt(view.aspect) : 0.0;
}

/// Under this many pixels across its narrow axis a ragged edge moves a polyp's aspect by a point
/// or more (1-2 points at 11-24 pixels, tests/app/polyp_check_test.cpp).
constexpr double kFewPixelsAcross = 25.0;

/// The term most responsible for a result's distance from the prediction (PolypViewResult).
std::string apartBecause(const PolypViewResult& result) {
    const double centreTerm = std::abs(result.centreAspectError - result.predicted.aspectError);
    const bool isOccluded = result.referenceUnoccludedShare < kFullViewShare ||
                            result.referenceHiddenInFrontShare > kMostHiddenInFront;
    const std::string centreCause = isOccluded ? "occlusion"
                                    : narrowAxisPixels(result.view) < kFewPixelsAcross ? "pixels"
                                                                                       : "outline";
    if (result.eye == Eye::Centre || !std::isfinite(result.exactWarpAspectError)) {
        const double eyeTerm = std::abs(result.aspectError - result.centreAspectError);
        if (result.eye != Eye::Centre && eyeTerm > centreTerm) return "eye";
        return centreCause;
    }
    const double warpTerm = std::abs(result.aspectError - result.exactWarpAspectError);
    const double eyeTerm = std::abs(result.exactWarpAspectError - result.centreAspectError);
    if (warpTerm >= eyeTerm && warpTerm >= centreTerm) return "warp";
    if (eyeTerm >= centreTerm) return "eye";
    return centreCause;
}

}  // namespace

PolypCheckPlan planPolypCheck(const PolypCheckJob& job, const CubeMapLookup& cubeMaps) {
    if (!(job.minAngularRadiusDeg > 0.0 && job.minAngularRadiusDeg <= job.angularRadiusDeg && job.angularRadiusDeg <= 30.0)) {
        throw std::invalid_argument("polyp check: the angular radii must satisfy 0 < least <= most <= 30 degrees");
    }
    Predictions predictions(job, cubeMaps);
    const auto targetOf = [&](const PolypPose& pose) {
        PoseTarget target;
        target.pose = pose;
        target.floor = errorsOf(predictions.at(conformal::MapKind::Conformal, pose, job.minAngularRadiusDeg));
        target.isTargeted = worstPredicted(target.floor) <= job.predictedTarget;
        return target;
    };
    PolypCheckPlan plan;
    for (const PolypPose& pose : job.poses.empty() ? polypPosesFor(job.display) : job.poses) plan.poses.push_back(targetOf(pose));
    // The radius comes from every pose of the display (and any of the job's own), whichever of
    // them are rendered: the plan's radius does not depend on the poses asked for. Each polyp's
    // place is judged at the poses rendered (worstPredictionFrom).
    std::vector<PoseTarget> ruling;
    for (const PolypPose& pose : polypPosesFor(job.display)) ruling.push_back(targetOf(pose));
    ruling.insert(ruling.end(), plan.poses.begin(), plan.poses.end());
    const auto worstAt = [&](double radiusDeg) {
        double worst = 0.0;
        for (const PoseTarget& target : ruling) {
            if (target.isTargeted) {
                worst = std::max(worst, worstPredicted(errorsOf(predictions.at(conformal::MapKind::Conformal, target.pose,
                                                                                radiusDeg))));
            }
        }
        return worst;
    };
    // The prediction grows with the radius (as its square, in the small): the largest radius up
    // to angularRadiusDeg, in quarter degrees, that keeps every targeted pose within the target.
    plan.angularRadiusDeg = job.angularRadiusDeg;
    while (plan.angularRadiusDeg - 0.25 >= job.minAngularRadiusDeg - 1e-9 && worstAt(plan.angularRadiusDeg) > job.predictedTarget) {
        plan.angularRadiusDeg -= 0.25;
    }
    // A polyp hidden from there (a bend or a fold in the way) comes closer a degree at a time,
    // up to 10 degrees more; at its poses whose prediction then exceeds the target, its results
    // are reported, not targeted (checkPolyps).
    plan.widestAngularRadiusDeg = std::min(plan.angularRadiusDeg + 10.0, 30.0);
    return plan;
}

std::vector<PolypViewResult> checkPolyps(Raycaster& raycaster, const PolypCheckJob& job, const PolypCheckPlan& plan,
                                         const CubeMapLookup& cubeMaps, const std::function<void(int, int)>& onProgress) {
    for (int index : job.polypIndices) {
        if (index < 0 || index >= static_cast<int>(job.polyps.size())) {
            throw std::invalid_argument("polyp " + std::to_string(index) + ": the ground truth lists " +
                                        std::to_string(job.polyps.size()) + " polyps");
        }
    }
    RenderSettings settings = job.settings;
    settings.isWritingHits = true;
    const std::size_t poseCount = plan.poses.size();
    const int total = static_cast<int>(job.polypIndices.size() * poseCount * (job.maps.size() + 1));
    int done = 0;
    const auto step = [&] {
        ++done;
        if (onProgress) onProgress(done, total);
    };
    Predictions predictions(job, cubeMaps);
    const std::vector<glm::dvec3> singular = singularDirectionsOf(job.display);

    // The poses, and the references from them (the pinhole needs no map), first.
    std::map<std::pair<int, std::size_t>, CameraPose> poses;
    std::map<std::tuple<int, std::size_t, Eye>, Reference> references;
    std::map<int, EyePlace> places;
    for (int index : job.polypIndices) {
        const colon::PolypSurface& polyp = job.polyps[static_cast<std::size_t>(index)];
        const EyePlace& place = places[index] = eyePlaceFor(raycaster, job, plan, predictions, polyp, settings);
        for (std::size_t p = 0; p < poseCount; ++p) {
            const CameraPose pose =
                poseSeeing(place.pose, colon::polypAimPointOf(polyp), plan.poses[p].pose.directionCave);
            poses[{index, p}] = pose;
            const ScenePose scene{pose.positionMm, pose.forward, pose.up, job.mmPerMetre};
            for (Eye eye : kEyes) {
                references[{index, p, eye}] = renderReference(raycaster, job, polyp, scene, eye, settings, CropChoice::Make);
            }
            step();
        }
    }

    std::vector<PolypViewResult> results;
    std::vector<colon::ViewSample> samples;  // one eye's walls, reused from view to view
    for (conformal::MapKind map : job.maps) {
        Display display = job.display;
        display.map = map;
        if (map != conformal::MapKind::None) {
            const conformal::CubeMap& cube = cubeMaps(map);
            raycaster.setCubeMap(cube.size, cube.rgba);
        }
        const WarpMode warp = map == conformal::MapKind::None ? WarpMode::None : job.warpMode;
        for (int index : job.polypIndices) {
            const colon::PolypSurface& polyp = job.polyps[static_cast<std::size_t>(index)];
            const EyePlace& place = places[index];
            const double radiusDeg = place.angularRadiusDeg;
            for (std::size_t p = 0; p < poseCount; ++p) {
                const PoseTarget& target = plan.poses[p];
                const CameraPose& pose = poses[{index, p}];
                const ScenePose scene{pose.positionMm, pose.forward, pose.up, job.mmPerMetre};
                const colon::PredictedShape prediction = predictions.ofOutline(map, polyp, pose);
                const colon::PredictedShape& circle = predictions.at(map, target.pose, radiusDeg);
                const std::vector<WallName> walls = wallsToRender(job, prediction, target.pose.directionCave,
                                                                  glm::radians(radiusDeg), map != conformal::MapKind::None);
                const std::vector<WallImage> images = renderSomeWalls(raycaster, display, walls, scene, kEyes, settings, job.warpMode);
                const PredictedErrors conformalOutline =
                    map == conformal::MapKind::Conformal
                        ? errorsOf(prediction)
                        : errorsOf(predictions.ofOutline(conformal::MapKind::Conformal, polyp, pose));
                const PredictedErrors conformalCircle =
                    errorsOf(predictions.at(conformal::MapKind::Conformal, target.pose, radiusDeg));
                const std::string untargetedBecause = untargetedBecauseOf(target, place.isInFullView, conformalOutline,
                                                                          conformalCircle, job.predictedTarget);
                const std::size_t first = results.size();
                for (Eye eye : kEyes) {
                    samplesOfEye(images, display, scene, eye, job.warpMode, samples);
                    const Reference& reference = references[{index, p, eye}];
                    PolypViewResult result;
                    result.polyp = index;
                    result.diameterMm = polyp.diameterMm;
                    result.pose = target.pose.name;
                    result.isTargeted = untargetedBecause.empty();
                    result.untargetedBecause = untargetedBecause;
                    result.missingWall = missingWallOf(job.display, target.pose.directionCave);
                    result.eye = eye;
                    result.map = map;
                    result.warp = warp;
                    result.cameraPose = pose;
                    result.angularRadiusDeg = radiusDeg;
                    result.reference = reference.measures;
                    result.referenceUnoccludedShare =
                        reference.unoccludedPixels > 0
                            ? static_cast<double>(reference.measures.pixels) / reference.unoccludedPixels
                            : 0.0;
                    result.referenceHiddenInFrontShare = hiddenInFrontShare(reference);
                    result.referenceCrop = reference.crop;
                    result.view = colon::measurePolypShape(samples, polyp, job.toleranceMm, reference.gridNormal);
                    const bool hasShape = result.view.pixels >= 3 && reference.measures.pixels >= 3;
                    // Without a map display directions are scene directions: the area the view
                    // shows, against the reference's, is the share of the polyp left on the walls.
                    if (map == conformal::MapKind::None) {
                        result.visibleFraction = hasShape ? result.view.areaSr / reference.measures.areaSr : 0.0;
                    }
                    result.isVisible = result.view.pixels >= colon::kMinPolypPixels &&
                                       reference.measures.pixels >= colon::kMinPolypPixels && result.visibleFraction >= 0.95;
                    const double nan = std::numeric_limits<double>::quiet_NaN();
                    result.aspectError = hasShape ? relativeError(result.view.aspect, reference.measures.aspect) : nan;
                    result.circularityError =
                        hasShape ? relativeError(result.view.circularity, reference.measures.circularity) : nan;
                    result.gridAngleErrorDeg =
                        hasShape ? std::abs(result.view.gridAngleDeg - reference.measures.gridAngleDeg) : nan;
                    if (result.view.pixels >= 3) {
                        const glm::dvec3 imageCave = glm::transpose(caveToVolumeRotation(scene)) * result.view.centreDirection;
                        result.singularDistanceDeg = singularDistanceDeg(singular, imageCave);
                    }
                    result.predicted = errorsOf(prediction);
                    result.predictedCircle = errorsOf(circle);
                    result.predictedFloor = target.floor;
                    const colon::ShapeMeasures& framing = result.view.pixels >= 3 ? result.view : reference.measures;
                    if (framing.pixels >= 3) {
                        result.crop = colon::tangentPlaneCrop(samples, framing.centreDirection, caveToVolumeRotation(scene)[0],
                                                              cropHalfWidth(framing), job.cropSize);
                    }
                    results.push_back(std::move(result));
                }
                // The budget: the centre eye's error beside each eye's, and where an eye is more
                // than a point from the prediction, the exact warp's for that eye.
                const double centreError = results[first + 1].aspectError;
                for (std::size_t r = first; r < results.size(); ++r) {
                    PolypViewResult& result = results[r];
                    result.centreAspectError = centreError;
                    if (map == conformal::MapKind::None || !result.isVisible || !result.predicted.isFound) continue;
                    if (!(std::abs(result.aspectError - result.predicted.aspectError) > 0.01)) continue;
                    if (result.eye != Eye::Centre && job.isRenderingExactWhereApart && job.warpMode != WarpMode::Exact) {
                        const std::array<Eye, 1> eye{result.eye};
                        const std::vector<WallImage> exact =
                            renderSomeWalls(raycaster, display, walls, scene, eye, settings, WarpMode::Exact);
                        samplesOfEye(exact, display, scene, result.eye, WarpMode::Exact, samples);
                        const colon::ShapeMeasures exactView = colon::measurePolypShape(
                            samples, polyp, job.toleranceMm, references[{index, p, result.eye}].gridNormal);
                        if (exactView.pixels >= 3) {
                            result.exactWarpAspectError = relativeError(exactView.aspect, result.reference.aspect);
                        }
                    }
                    result.apartBecause = apartBecause(result);
                }
                step();
            }
        }
    }
    return results;
}

}  // namespace engine
