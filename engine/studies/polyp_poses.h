/// @brief Where polyp-check puts a polyp in a display's view, from the display's own walls: the
/// poses (directions of the polyp from the map centre, in CAVE axes), the pose of the camera
/// that puts a point there, and the display's singular points that a polyp's image is measured
/// against.
#pragma once

#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "engine/display/display_description.h"
#include "engine/sequence/camera_path.h"

namespace engine {

/// A polyp's place in the view: its unit direction from the map centre in CAVE axes (x right,
/// y up, z back).
struct PolypPose {
    std::string name;
    glm::dvec3 directionCave{0.0, 0.0, -1.0};
};

/// Elevation above the horizon and azimuth to the right of straight ahead (-z), degrees, of a
/// CAVE direction: elevation in [-90, 90], azimuth in (-180, 180].
glm::dvec2 elevationAzimuthDegOf(const glm::dvec3& directionCave);
/// The CAVE direction at `elevationDeg` above the horizon and `azimuthDeg` to the right of
/// straight ahead; past 90 degrees of elevation, over the head and behind.
glm::dvec3 caveDirectionOf(double elevationDeg, double azimuthDeg);

/// The poses for a display that lacks walls (DESIGN.md: the map opens them onto the present
/// ones). They follow the sweep from straight ahead over the middle of the missing walls (for
/// the cabin and cave4: up over the head and on behind), measured in degrees s along it from
/// straight ahead, with [s0, s1] the part of the sweep on missing walls:
///  - "wall": 15 degrees along (or 15 before s0, if that is less), on the front wall;
///  - "edge": 9 degrees before s0, the polyp's top near the missing walls' edge;
///  - "<wall>_<s>" at s0 + 7, s0 + 13 and s0 + 23, on the missing wall named, near its edge,
///    and at the quarter, middle and three quarters of [s0, s1];
///  - "<wall>_<s>_side": the middle and three quarters of [s0, s1] turned 30 degrees to the
///    side, off the plane of symmetry, where the map's slit runs for the cabin and cave4;
///  - "corner": 5 degrees beyond the slit tip nearest straight ahead (a corner of the missing
///    walls' boundary), away from the present walls.
/// For the cabin: wall 15, edge 28, ceiling_44, _50, _60, _63, _90, _117, ceiling_90_side,
/// ceiling_117_side and corner (33 degrees up at 45 degrees azimuth). Which of them are
/// targeted is decided by what the map itself costs there (polyp_check.h). Throws
/// std::invalid_argument for a display that lacks no wall.
std::vector<PolypPose> polypPosesFor(const Display& display);

/// The display's poses named in `names` (every pose for an empty list), in the display's order; throws
/// std::invalid_argument naming an unknown pose and listing the display's.
std::vector<PolypPose> polypPosesNamed(const Display& display, const std::vector<std::string>& names);

/// The pose at `base`'s position turned so that `pointMm` lies along `directionCave` from it, as
/// close to `base`'s view as that allows. Throws std::invalid_argument when the point is at the
/// position.
CameraPose poseSeeing(const CameraPose& base, const glm::dvec3& pointMm, const glm::dvec3& directionCave);

/// The display's singular points, unit CAVE directions from the map centre: the corners of the
/// missing walls' boundary (where the slit ends, and the convex corners) and the midpoints of its
/// edges (the cabin's are where the map sends the slit's meeting point, the zenith).
std::vector<glm::dvec3> singularDirectionsOf(const Display& display);

/// The angle in degrees from a CAVE direction to the nearest of `singular`.
double singularDistanceDeg(const std::vector<glm::dvec3>& singular, const glm::dvec3& directionCave);

/// The wall the display lacks that the ray from the map centre along `directionCave` leaves the
/// box through, or nothing (empty) when it leaves through a present one.
std::string missingWallOf(const Display& display, const glm::dvec3& directionCave);

}  // namespace engine
