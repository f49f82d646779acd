/// @brief The colon phantom's tube in tube coordinates (arc length along the centreline, angle
/// around it): the smoothed centreline with a twist-free frame, and the haustral folds that pull
/// the wall in. Internal to the phantom (colon_phantom.cpp, phantom_polyps.cpp).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include <glm/glm.hpp>

#include "volumes/colon_phantom.h"

namespace volumes {

/// Catmull-Rom spline through `points`, sampled every ~1 mm along its length.
std::vector<glm::dvec3> smoothPolyline(const std::vector<glm::dvec3>& points);

/// The centreline with arc lengths and a rotation-minimising frame (Wang et al. 2008, double
/// reflection), so "angle around the centreline" does not twist along the tube.
struct Centreline {
    std::vector<glm::dvec3> points, tangents, normals;
    std::vector<double> arcMm;

    explicit Centreline(std::vector<glm::dvec3> polyline);
    double length() const { return arcMm.back(); }

    /// Point, tangent and normal at arc length s (clamped), interpolated between vertices.
    void frameAt(double s, glm::dvec3& point, glm::dvec3& tangent, glm::dvec3& normal) const {
        s = std::clamp(s, 0.0, length());
        const std::size_t i =
            std::min<std::size_t>(std::upper_bound(arcMm.begin(), arcMm.end(), s) - arcMm.begin(), points.size() - 1);
        const std::size_t a = i == 0 ? 0 : i - 1;
        const double span = arcMm[i] - arcMm[a];
        const double t = span > 0.0 ? (s - arcMm[a]) / span : 0.0;
        point = glm::mix(points[a], points[i], t);
        tangent = glm::normalize(glm::mix(tangents[a], tangents[i], t));
        normal = glm::mix(normals[a], normals[i], t);
        normal = glm::normalize(normal - glm::dot(normal, tangent) * tangent);
    }
};

/// A haustral fold: where it is along the colon and the angle of its deepest part.
struct Fold {
    double arcMm;
    double angleRad;
};

/// How far the lumen wall is pulled in by haustral folds at arc s and angle theta (mm).
double foldIntrusion(const ColonPhantomSpec& spec, const std::vector<Fold>& folds, double s, double theta);
/// foldIntrusion's `around` is 1 (full depth) where cos(theta - fold angle) >= 0.3 and 0 (its
/// gap) where cos <= -0.5.
inline const double kFoldFullDepthHalfAngleRad = std::acos(0.3);
inline const double kFoldHalfAngleRad = std::acos(-0.5);

}  // namespace volumes
