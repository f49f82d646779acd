#include "volumes/polyline.h"

#include <algorithm>

namespace volumes {

double distanceToSegmentMm(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, double* t) {
    const glm::dvec3 ab = b - a;
    const double length2 = glm::dot(ab, ab);
    const double along = length2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / length2, 0.0, 1.0) : 0.0;
    if (t) *t = along;
    return glm::length(p - (a + along * ab));
}

double polylineLength(const std::vector<glm::dvec3>& points) {
    double length = 0.0;
    for (std::size_t i = 1; i < points.size(); ++i) length += glm::length(points[i] - points[i - 1]);
    return length;
}

std::vector<glm::dvec3> resampleByArc(const std::vector<glm::dvec3>& points, double stepMm) {
    if (points.size() < 2 || !(stepMm > 0.0)) return points;
    std::vector<glm::dvec3> out{points.front()};
    double carried = 0.0;  // arc since the last output point, carried over from earlier segments
    for (std::size_t i = 1; i < points.size(); ++i) {
        glm::dvec3 from = points[i - 1];
        double length = glm::length(points[i] - from);
        while (carried + length >= stepMm && length > 0.0) {
            from = from + ((stepMm - carried) / length) * (points[i] - from);
            out.push_back(from);
            length = glm::length(points[i] - from);
            carried = 0.0;
        }
        carried += length;
    }
    if (glm::length(out.back() - points.back()) > 0.25 * stepMm) out.push_back(points.back());
    return out;
}

}  // namespace volumes
