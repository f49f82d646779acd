/// @brief Camera poses along a path through the colon: centrelines read from a phantom's
/// ground truth or a text file, resampled by arc length, smoothed, in either direction.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "engine/render/camera_pose.h"

namespace engine {

/// A centreline read from a file, in antegrade order (rectum -> caecum, the endoscope's
/// direction), in one or more segments with gaps of tissue between them.
struct Centreline {
    std::vector<std::vector<glm::dvec3>> segments;
    /// The patient's anterior in volume millimetres, where the file records it (`cvc colon`
    /// takes it from the scan's orientation matrix): the first pose's up.
    std::optional<glm::dvec3> anterior;
};

/// Reads a centreline in volume millimetres: the "centreline_mm" array of a JSON file (a
/// phantom's ground truth from `cvc phantom`, or `cvc colon`'s colon.json, split into segments
/// at its "segment_starts"), or a text file with one "x y z" point per line ('#' starts a
/// comment, a line "# segment N" starts a new segment; commas may separate). A JSON file's
/// "centreline_order" says which way it runs ("rectum_to_caecum", the default, or
/// "caecum_to_rectum", as the phantom's does); the result always runs rectum -> caecum. A
/// text file is taken to run rectum -> caecum. Throws std::runtime_error naming the file and
/// line for a missing file, a malformed line, non-finite numbers, an unknown order, or a segment
/// of fewer than two distinct points.
Centreline readCentreline(const std::string& path);

/// readCentreline's segments joined into one polyline (rectum -> caecum).
std::vector<glm::dvec3> readPolyline(const std::string& path);

enum class Direction { Antegrade, Retrograde };

struct PathSettings {
    double stepMm = 2.0;            // arc length between frames
    double smoothingMm = 8.0;       // half-width of the window the view direction is averaged over
    Direction direction = Direction::Antegrade;
    glm::dvec3 initialUp{0.0, -1.0, 0.0};  // up of the first frame (made orthogonal), then carried along
    int maxFrames = 100000;         // a bound on the frames one path may produce
};

/// Poses along every segment of `centreline` in turn (rectum -> caecum, or caecum -> rectum
/// for Retrograde), stepMm apart within a segment, up carried on across the gaps; a segment
/// shorter than one step is skipped. Throws std::invalid_argument as posesAlong does, or when
/// no segment is one step long.
std::vector<CameraPose> posesAlongSegments(const Centreline& centreline, const PathSettings& settings);

/// The segment of `centreline` that passes nearest to `pointMm` (a polyp is seen from its own
/// segment). Throws std::invalid_argument for a centreline without segments.
const std::vector<glm::dvec3>& nearestSegment(const Centreline& centreline, const glm::dvec3& pointMm);

/// Poses every stepMm along `polyline` (start to end, or end to start for Retrograde), looking
/// along the tangent averaged over +-smoothingMm of arc, with up carried by parallel transport
/// (a rotation-minimizing frame), so the view never spins about the path. Throws
/// std::invalid_argument for bad settings or a polyline shorter than one step.
std::vector<CameraPose> posesAlong(const std::vector<glm::dvec3>& polyline, const PathSettings& settings);

/// The pose on `polyline` from which `pointMm` is seen ahead at `elevationDeg` above the
/// horizon (90: straight overhead; past 90 over the head and behind the viewer), looking along
/// the path in `settings`'s direction, with up turned toward the point. At elevations above
/// ~37 degrees the point lies on the ceiling of the Immersive Cabin, past about 135 on the
/// back wall that the 4-wall CAVE lacks; only the conformal map brings them onto the walls.
/// Throws std::invalid_argument for an elevation outside (0, 180).
/// `azimuthDeg` turns up about the view direction so that the point is seen that many degrees
/// to the right of straight up (0: overhead; behind the viewer, off the display's mirror plane).
CameraPose poseViewing(const std::vector<glm::dvec3>& polyline, const glm::dvec3& pointMm, double elevationDeg,
                       const PathSettings& settings, double azimuthDeg = 0.0);

/// The polyp centres ("polyps"[i]["centre_mm"]) of a phantom's JSON ground truth, in volume
/// millimetres. Throws std::runtime_error naming the file for a missing or malformed list.
std::vector<glm::dvec3> readPolypCentres(const std::string& path);

/// The candidate centres ("candidates"[i]["centre_mm"], best first) of `cvc candidates`'
/// candidates.json, in volume millimetres. Throws std::runtime_error naming the file for a
/// missing or malformed list, or one without candidates.
std::vector<glm::dvec3> readCandidateCentres(const std::string& path);

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
    std::string candidatesFile;        // non-empty: one pose viewing each candidate of this file, in its order
    double polypElevationDeg = 60.0;   // the elevation (and azimuth) a polyp or candidate is seen at
    double polypAzimuthDeg = 0.0;
    std::optional<glm::dvec3> positionMm;
    std::optional<glm::dvec3> lookAtMm;
    glm::dvec3 up{0.0, 0.0, 1.0};
};

/// The poses `request` asks for. Throws std::invalid_argument (or std::runtime_error for an
/// unreadable file) naming what is wrong: no path and no position, a polyp the file lacks.
std::vector<CameraPose> posesFor(const PoseRequest& request);

}  // namespace engine
