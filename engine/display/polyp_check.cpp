#include "engine/display/polyp_check.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <tuple>

#include "engine/display/frame_sequence.h"
#include "engine/display/view_samples.h"
#include "engine/render/pinhole_camera.h"

namespace engine {
namespace {

constexpr std::array<Eye, 2> kEyes{Eye::Left, Eye::Right};

/// Whether the direction `toPointVolume` from the map centre leaves the CAVE box through its
/// ceiling (the wall the 5-wall cabin lacks).
bool isTowardCeiling(const Display& display, const ScenePose& pose, const glm::dvec3& toPointVolume) {
    const glm::dvec3 d = glm::transpose(caveToVolumeRotation(pose)) * glm::normalize(toPointVolume);
    const glm::dvec3 half = 0.5 * display.boxSizeM;
    double nearest = std::numeric_limits<double>::max();
    int face = -1;  // 2 * axis + (positive side)
    for (int a = 0; a < 3; ++a) {
        if (d[a] == 0.0) continue;  // parallel to this pair of faces: never leaves through them
        const double bound = d[a] > 0.0 ? half[a] : -half[a];
        const double t = (bound - display.mapCentreM[a]) / d[a];
        if (t > 0.0 && t < nearest) {
            nearest = t;
            face = 2 * a + (d[a] > 0.0 ? 1 : 0);
        }
    }
    return face == 3;  // +y
}

/// The angle from display direction `direction` (volume axes) to the nearest corner or edge
/// midpoint of the CAVE's ceiling, seen from the map centre.
double singularDistanceDeg(const Display& display, const ScenePose& pose, const glm::dvec3& direction) {
    const glm::dvec3 d = glm::normalize(glm::transpose(caveToVolumeRotation(pose)) * direction);
    const glm::dvec3 half = 0.5 * display.boxSizeM;
    double nearest = 180.0;
    for (int i = -1; i <= 1; ++i)
        for (int k = -1; k <= 1; ++k) {
            if (i == 0 && k == 0) continue;  // the ceiling's centre is not on its boundary
            const glm::dvec3 point = glm::dvec3(i * half.x, half.y, k * half.z) - display.mapCentreM;
            nearest = std::min(nearest, glm::degrees(std::acos(std::clamp(glm::dot(d, glm::normalize(point)), -1.0, 1.0))));
        }
    return nearest;
}

struct Reference {
    colon::ShapeMeasures measures;
    colon::RgbaImage crop;
    glm::dvec3 gridNormal{0.0};  ///< the line of sight the painted grid faces
};

/// The tangent-plane half-width of a view's crop: the polyp at the same relative size in each.
double cropHalfWidth(const colon::ShapeMeasures& measures) { return 1.8 * std::sqrt(measures.areaSr / 3.14159265358979); }

/// Whether a reference also makes its crop: not while searching for the eye's place, where only
/// the polyp's pixels count.
enum class CropChoice { Make, Skip };

/// The pinhole reference from `eye`'s position at `scene`, aimed at the polyp, framing it.
Reference renderReference(Raycaster& raycaster, const PolypCheckJob& job, const colon::PolypSurface& polyp,
                          const ScenePose& scene, Eye eye, const RenderSettings& settings, CropChoice crop) {
    const glm::dvec3 eyeMm = wallView(job.display, WallName::Front, eye, scene, WarpMode::None).rays.eyeMm;
    const double distance = glm::length(polyp.centreMm - eyeMm);
    const double angularRadius = std::asin(std::min(1.0, (0.5 * polyp.diameterMm + 1.0) / distance));
    PinholeCamera camera;
    camera.positionMm = eyeMm;
    camera.lookAtMm = polyp.centreMm;
    camera.up = scene.up;
    camera.verticalFovDeg = std::clamp(glm::degrees(3.0 * angularRadius), 5.0, 150.0);
    camera.width = camera.height = job.referenceSize;
    const ViewRays rays = viewRaysFrom(camera);
    const RenderedImage image = raycaster.render(rays, settings);
    const std::vector<colon::ViewSample> samples = viewSamples(rays, image);
    Reference reference;
    reference.gridNormal = glm::normalize(polyp.centreMm - eyeMm);
    reference.measures = colon::measurePolypShape(samples, polyp, job.toleranceMm, reference.gridNormal);
    if (crop == CropChoice::Make && reference.measures.pixels >= 3) {
        const glm::dvec3 right = caveToVolumeRotation(scene)[0];
        reference.crop = colon::tangentPlaneCrop(samples, reference.measures.centreDirection, right,
                                                 cropHalfWidth(reference.measures), job.cropSize);
    }
    return reference;
}

/// Whether the polyp is in full view from the centre eye at `pose`: the reference sees at least
/// 40 % of the disc it would fill unoccluded (folds and bends hide polyps from far back).
bool isInFullView(Raycaster& raycaster, const PolypCheckJob& job, const colon::PolypSurface& polyp,
                  const CameraPose& pose, const RenderSettings& settings) {
    const ScenePose scene{pose.positionMm, pose.forward, pose.up, job.mmPerMetre};
    const Reference reference = renderReference(raycaster, job, polyp, scene, Eye::Centre, settings, CropChoice::Skip);
    const double expectedRadius = 0.5 * job.referenceSize / 1.5;  // the framing puts 1.5 radii at the edge
    return reference.measures.pixels >= 0.4 * 3.14159265358979 * expectedRadius * expectedRadius;
}

/// Poses tried at one distance, and how far the angular radius may grow when none has the
/// polyp in full view.
constexpr int kCandidates = 12;
constexpr int kMaxWideningDeg = 4;

/// The path's pose from which `polyp` subtends job.angularRadiusDeg (or up to kMaxWideningDeg
/// more, set in `angularRadiusDeg`) and is in full view: among the poses within 10 % of that
/// distance, those before the polyp (antegrade) first. Falls back to the pose nearest the
/// distance when none has the polyp in full view.
CameraPose eyePoseFor(Raycaster& raycaster, const PolypCheckJob& job, const colon::PolypSurface& polyp,
                      const RenderSettings& settings, double& angularRadiusDeg) {
    PathSettings fine = job.path;
    fine.stepMm = 0.5;
    const std::vector<CameraPose> poses = posesAlong(nearestSegment(job.centreline, polyp.centreMm), fine);
    const auto distanceTo = [&](const CameraPose& pose) { return glm::length(pose.positionMm - polyp.centreMm); };
    const auto nearest = static_cast<std::size_t>(
        std::min_element(poses.begin(), poses.end(),
                         [&](const CameraPose& a, const CameraPose& b) { return distanceTo(a) < distanceTo(b); }) -
        poses.begin());
    // Far back, a fold or a bend may hide the polyp: then come closer, a degree at a time.
    for (int widening = 0; widening <= kMaxWideningDeg; ++widening) {
        angularRadiusDeg = job.angularRadiusDeg + widening;
        const double wanted = 0.5 * polyp.diameterMm / std::sin(glm::radians(angularRadiusDeg));
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
    }
    angularRadiusDeg = job.angularRadiusDeg;
    const double wanted = 0.5 * polyp.diameterMm / std::sin(glm::radians(angularRadiusDeg));
    return *std::min_element(poses.begin(), poses.end(), [&](const CameraPose& a, const CameraPose& b) {
        return std::abs(distanceTo(a) - wanted) < std::abs(distanceTo(b) - wanted);
    });
}

double relativeError(double value, double reference) {
    return reference != 0.0 ? std::abs(value - reference) / std::abs(reference) : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

std::vector<PolypPose> defaultPolypPoses() {
    return {{"wall", 15.0, 0.0, true},         {"edge", 28.0, 0.0, true},
            {"ceiling_44", 44.0, 0.0, true},   {"ceiling_50", 50.0, 0.0, true},
            {"ceiling_60", 60.0, 0.0, false},  {"corner", 33.0, 45.0, false}};
}

CameraPose poseSeeing(const CameraPose& base, const glm::dvec3& pointMm, double elevationDeg, double azimuthDeg) {
    const glm::dvec3 toPoint = pointMm - base.positionMm;
    if (!(glm::length(toPoint) > 1e-9)) throw std::invalid_argument("pose: the point is at the position");
    const double el = glm::radians(elevationDeg), az = glm::radians(azimuthDeg);
    // In the frame (forward, y, up) with right = forward x up = -y, the point's direction is:
    const glm::dvec3 v1(std::cos(el) * std::cos(az), -std::cos(el) * std::sin(az), std::sin(el));
    glm::dvec3 v2 = glm::dvec3(1, 0, 0) - v1.x * v1;
    if (glm::length(v2) < 1e-9) v2 = glm::dvec3(0, 0, 1) - v1.z * v1;
    v2 = glm::normalize(v2);
    const glm::dvec3 v3 = glm::cross(v1, v2);
    // ... and in volume axes it is d; the frame's forward stays as close to base's as it can.
    const glm::dvec3 d = glm::normalize(toPoint);
    glm::dvec3 g = base.forward - glm::dot(base.forward, d) * d;
    if (glm::length(g) < 1e-9) g = base.up - glm::dot(base.up, d) * d;
    g = glm::normalize(g);
    const glm::dvec3 h = glm::cross(d, g);
    const glm::dmat3 rotation = glm::dmat3(d, g, h) * glm::transpose(glm::dmat3(v1, v2, v3));
    CameraPose pose;
    pose.positionMm = base.positionMm;
    pose.forward = glm::normalize(rotation * glm::dvec3(1, 0, 0));
    pose.up = glm::normalize(rotation * glm::dvec3(0, 0, 1));
    return pose;
}

std::vector<PolypViewResult> checkPolyps(Raycaster& raycaster, const PolypCheckJob& job, const CubeMapLookup& cubeMaps,
                                         const std::function<void(int, int)>& onProgress) {
    for (int index : job.polypIndices) {
        if (index < 0 || index >= static_cast<int>(job.polyps.size())) {
            throw std::invalid_argument("polyp " + std::to_string(index) + ": the ground truth lists " +
                                        std::to_string(job.polyps.size()) + " polyps");
        }
    }
    RenderSettings settings = job.settings;
    settings.isWritingHits = true;
    const int total = static_cast<int>(job.polypIndices.size() * job.poses.size() * (job.maps.size() + 1));
    int done = 0;
    const auto step = [&] {
        ++done;
        if (onProgress) onProgress(done, total);
    };

    // The poses, and the references from them (the pinhole needs no map), first.
    std::map<std::pair<int, std::size_t>, CameraPose> poses;
    std::map<std::tuple<int, std::size_t, Eye>, Reference> references;
    std::map<int, double> angularRadii;
    for (int index : job.polypIndices) {
        const colon::PolypSurface& polyp = job.polyps[static_cast<std::size_t>(index)];
        double angularRadiusDeg = job.angularRadiusDeg;
        const CameraPose base = eyePoseFor(raycaster, job, polyp, settings, angularRadiusDeg);
        angularRadii[index] = angularRadiusDeg;
        for (std::size_t p = 0; p < job.poses.size(); ++p) {
            const PolypPose& wanted = job.poses[p];
            const CameraPose pose = poseSeeing(base, polyp.centreMm, wanted.elevationDeg, wanted.azimuthDeg);
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
        for (int index : job.polypIndices) {
            const colon::PolypSurface& polyp = job.polyps[static_cast<std::size_t>(index)];
            for (std::size_t p = 0; p < job.poses.size(); ++p) {
                const CameraPose& pose = poses[{index, p}];
                const ScenePose scene{pose.positionMm, pose.forward, pose.up, job.mmPerMetre};
                const std::vector<WallImage> walls = renderWalls(raycaster, display, scene, kEyes, settings, job.warpMode);
                for (Eye eye : kEyes) {
                    samples.clear();
                    for (const WallImage& wall : walls) {
                        if (wall.eye != eye) continue;
                        appendViewSamples(wallView(display, wall.wall, eye, scene, job.warpMode).rays, wall.image, samples);
                    }
                    const Reference& reference = references[{index, p, eye}];
                    PolypViewResult result;
                    result.polyp = index;
                    result.diameterMm = polyp.diameterMm;
                    result.pose = job.poses[p].name;
                    result.isTargeted = job.poses[p].isTargeted;
                    result.isOnCeiling = isTowardCeiling(job.display, scene, polyp.centreMm - pose.positionMm);
                    result.eye = eye;
                    result.map = map;
                    result.cameraPose = pose;
                    result.angularRadiusDeg = angularRadii[index];
                    result.reference = reference.measures;
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
                        result.singularDistanceDeg = singularDistanceDeg(job.display, scene, result.view.centreDirection);
                    }
                    const colon::ShapeMeasures& framing = result.view.pixels >= 3 ? result.view : reference.measures;
                    if (framing.pixels >= 3) {
                        result.crop = colon::tangentPlaneCrop(samples, framing.centreDirection, caveToVolumeRotation(scene)[0],
                                                              cropHalfWidth(framing), job.cropSize);
                    }
                    results.push_back(std::move(result));
                }
                step();
            }
        }
    }
    return results;
}

}  // namespace engine
