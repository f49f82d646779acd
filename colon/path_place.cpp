#include "colon/path_place.h"

#include <algorithm>
#include <limits>

namespace colon {

PathPlace placeOnPath(const std::vector<std::vector<glm::dvec3>>& segments, const glm::dvec3& pointMm,
                      const std::vector<glm::dvec3>& framePositionsMm) {
    PathPlace place;
    double best = std::numeric_limits<double>::infinity();
    double arcBefore = 0.0;  // the lengths of the segments before this one
    for (std::size_t s = 0; s < segments.size(); ++s) {
        const auto& line = segments[s];
        double arc = 0.0;
        for (std::size_t i = 0; i + 1 < line.size(); ++i) {
            const glm::dvec3 piece = line[i + 1] - line[i];
            const double length = glm::length(piece);
            // The nearest point of the piece; a piece of zero length is its start.
            const double t = length > 0.0 ? std::clamp(glm::dot(pointMm - line[i], piece) / (length * length), 0.0, 1.0) : 0.0;
            const glm::dvec3 nearest = line[i] + t * piece;
            const double distance = glm::length(pointMm - nearest);
            if (distance < best) {
                best = distance;
                place.segment = static_cast<int>(s);
                place.arcLengthMm = arcBefore + arc + t * length;
                place.pointMm = nearest;
                place.distanceMm = distance;
            }
            arc += length;
        }
        arcBefore += arc;
    }
    if (place.segment < 0) return place;
    double nearestFrame = std::numeric_limits<double>::infinity();
    for (std::size_t f = 0; f < framePositionsMm.size(); ++f) {
        const double distance = glm::length(framePositionsMm[f] - place.pointMm);
        if (distance < nearestFrame) {
            nearestFrame = distance;
            place.nearestFrame = static_cast<int>(f);
        }
    }
    return place;
}

}  // namespace colon
