/// @brief Camera poses along a path through the colon: centrelines read from a phantom's
/// ground truth or a text file, resampled by arc length, smoothed, in either direction.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace engine {

/// Where the viewer is and where it looks, in volume millimetres (forward and up are unit,
/// orthogonal).
struct CameraPose {
    glm::dvec3 positionMm{0.0};
    glm::dvec3 forward{0.0, 0.0, 1.0};
    glm::dvec3 up{0.0, 1.0, 0.0};
};

/// Reads a polyline in volume millimetres: the "centreline_mm" array of a phantom's JSON
/// ground truth (`cvc phantom`), or a text file with one "x y z" point per line ('#' starts a
/// comment; commas may separate). Throws std::runtime_error naming the file and line for a
/// missing file, a malformed line, non-finite numbers, or fewer than two distinct points.
std::vector<glm::dvec3> readPolyline(const std::string& path);

enum class Direction { Antegrade, Retrograde };

struct PathSettings {
    double stepMm = 2.0;            // arc length between frames
    double smoothingMm = 8.0;       // half-width of the window the view direction is averaged over
    Direction direction = Direction::Antegrade;
    glm::dvec3 initialUp{0.0, -1.0, 0.0};  // up of the first frame (made orthogonal), then carried along
    int maxFrames = 100000;         // a bound on the frames one path may produce
};

/// Poses every stepMm along `polyline` (start to end, or end to start for Retrograde), looking
/// along the tangent averaged over +-smoothingMm of arc, with up carried by parallel transport
/// (a rotation-minimizing frame), so the view never spins about the path. Throws
/// std::invalid_argument for bad settings or a polyline shorter than one step.
std::vector<CameraPose> posesAlong(const std::vector<glm::dvec3>& polyline, const PathSettings& settings);

/// The pose on `polyline` from which `pointMm` is seen ahead at `elevationDeg` above the
/// horizon (90: straight overhead), looking along the path in `settings`'s direction, with up
/// turned toward the point. At elevations above ~37 degrees the point lies on the ceiling of
/// the Immersive Cabin, which only the conformal map brings onto the walls. Throws
/// std::invalid_argument for an elevation outside (0, 90].
CameraPose poseViewing(const std::vector<glm::dvec3>& polyline, const glm::dvec3& pointMm, double elevationDeg,
                       const PathSettings& settings);

/// The polyp centres ("polyps"[i]["centre_mm"]) of a phantom's JSON ground truth, in volume
/// millimetres. Throws std::runtime_error naming the file for a missing or malformed list.
std::vector<glm::dvec3> readPolypCentres(const std::string& path);

/// The pose at `positionMm` looking at `lookAtMm`, with `up` made orthogonal to the view.
/// Throws std::invalid_argument when the two points coincide or up is parallel to the view.
CameraPose poseLookingAt(const glm::dvec3& positionMm, const glm::dvec3& lookAtMm, const glm::dvec3& up);

/// Where a display render's poses come from: a path file (every pose along it, or the one pose
/// viewing a polyp of its ground truth), or one pose given by position and look-at point.
struct PoseRequest {
    std::string pathFile;
    PathSettings path;
    int maxFrames = 0;                 // 0: every pose of the path
    int polyp = -1;                    // >= 0: the pose viewing this polyp of the path's ground truth
    double polypElevationDeg = 60.0;
    std::optional<glm::dvec3> positionMm;
    std::optional<glm::dvec3> lookAtMm;
    glm::dvec3 up{0.0, 0.0, 1.0};
};

/// The poses `request` asks for. Throws std::invalid_argument (or std::runtime_error for an
/// unreadable file) naming what is wrong: no path and no position, a polyp the file lacks.
std::vector<CameraPose> posesFor(const PoseRequest& request);

}  // namespace engine
