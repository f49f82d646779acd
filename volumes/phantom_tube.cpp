#include "volumes/phantom_tube.h"

#include <utility>

#include "volumes/polyline.h"

namespace volumes {
namespace {

/// Centreline vertices are this far apart along the curve.
constexpr double kCentrelineStepMm = 1.0;

}  // namespace

std::vector<glm::dvec3> smoothPolyline(const std::vector<glm::dvec3>& points) {
    std::vector<glm::dvec3> dense;
    const int spans = static_cast<int>(points.size()) - 1;
    for (int i = 0; i < spans; ++i) {
        const glm::dvec3 p0 = points[static_cast<std::size_t>(std::max(i - 1, 0))];
        const glm::dvec3 p1 = points[static_cast<std::size_t>(i)];
        const glm::dvec3 p2 = points[static_cast<std::size_t>(i + 1)];
        const glm::dvec3 p3 = points[static_cast<std::size_t>(std::min(i + 2, spans))];
        for (int s = 0; s < 200; ++s) {
            const double t = s / 200.0, t2 = t * t, t3 = t2 * t;
            dense.push_back(0.5 * ((2.0 * p1) + (-p0 + p2) * t + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * t2 +
                                   (-p0 + 3.0 * p1 - 3.0 * p2 + p3) * t3));
        }
    }
    dense.push_back(points.back());
    return resampleByArc(dense, kCentrelineStepMm);
}

Centreline::Centreline(std::vector<glm::dvec3> polyline) : points(std::move(polyline)) {
    const std::size_t n = points.size();
    arcMm.assign(n, 0.0);
    for (std::size_t i = 1; i < n; ++i) arcMm[i] = arcMm[i - 1] + glm::length(points[i] - points[i - 1]);
    tangents.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        tangents[i] = glm::normalize(points[std::min(i + 1, n - 1)] - points[i == 0 ? 0 : i - 1]);
    }
    normals.resize(n);
    const glm::dvec3 t0 = tangents[0];
    const glm::dvec3 helper = std::abs(t0.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    normals[0] = glm::normalize(glm::cross(t0, glm::cross(helper, t0)));
    for (std::size_t i = 0; i + 1 < n; ++i) {
        const glm::dvec3 v1 = points[i + 1] - points[i];
        const double c1 = glm::dot(v1, v1);
        const glm::dvec3 rL = normals[i] - (2.0 / c1) * glm::dot(v1, normals[i]) * v1;
        const glm::dvec3 tL = tangents[i] - (2.0 / c1) * glm::dot(v1, tangents[i]) * v1;
        const glm::dvec3 v2 = tangents[i + 1] - tL;
        const double c2 = glm::dot(v2, v2);
        glm::dvec3 next = c2 > 1e-20 ? rL - (2.0 / c2) * glm::dot(v2, rL) * v2 : rL;
        next -= glm::dot(next, tangents[i + 1]) * tangents[i + 1];
        normals[i + 1] = glm::normalize(next);
    }
}

double foldIntrusion(const ColonPhantomSpec& spec, const std::vector<Fold>& folds, double s, double theta) {
    double intrusion = 0.0;
    for (const Fold& fold : folds) {
        const double x = (s - fold.arcMm) / spec.foldHalfWidthMm;
        if (std::abs(x) >= 1.0) continue;
        // Semilunar: the ridge spans two thirds of the circumference, deepest opposite its gap.
        const double around = std::clamp((std::cos(theta - fold.angleRad) + 0.5) / 0.8, 0.0, 1.0);
        intrusion = std::max(intrusion, spec.foldDepthMm * (1.0 - x * x) * around);
    }
    return intrusion;
}

}  // namespace volumes
