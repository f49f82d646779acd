/// @brief Where a point of the colon wall lies along the path flown through it: the nearest
/// point of the centreline, its arc length from the path's start (rectum -> caecum, the gaps
/// between segments not counted), and the frame of a fly-through posed nearest to it.
#pragma once

#include <vector>

#include <glm/glm.hpp>

namespace colon {

struct PathPlace {
    int segment = -1;          ///< 0-based, in the path's order
    double arcLengthMm = 0.0;  ///< from the start of the first segment, over the segments' own lengths
    glm::dvec3 pointMm{0.0};   ///< the nearest point on the centreline
    double distanceMm = 0.0;   ///< from the point given to pointMm
    int nearestFrame = -1;     ///< the frame position nearest pointMm; -1 without frames
};

/// The place of `pointMm` on `segments` (each a polyline; segments of fewer than two points
/// are passed over), and the index of the entry of `framePositionsMm` nearest that place.
/// A point off every segment (none has two points) gives segment -1.
PathPlace placeOnPath(const std::vector<std::vector<glm::dvec3>>& segments, const glm::dvec3& pointMm,
                      const std::vector<glm::dvec3>& framePositionsMm);

}  // namespace colon
