/// @brief Polylines in volume millimetres: length and resampling by arc length, shared by the
/// phantom's centreline and the centrelines the colon analysis extracts.
#pragma once

#include <vector>

#include <glm/glm.hpp>

namespace volumes {

/// Distance from p to the segment a-b; `t` (if given) gets the nearest point's parameter, 0 at
/// a and 1 at b.
double distanceToSegmentMm(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, double* t = nullptr);

/// The sum of the segment lengths.
double polylineLength(const std::vector<glm::dvec3>& points);

/// Points every stepMm of arc length from the first, the last point kept unless it lies within
/// a quarter step of the previous one. Fewer than two points, or a step that is not positive,
/// return the input.
std::vector<glm::dvec3> resampleByArc(const std::vector<glm::dvec3>& points, double stepMm);

}  // namespace volumes
