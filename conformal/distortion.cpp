/// @brief Finite-difference Jacobians of baked maps and their statistics.
#include "conformal/distortion.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

namespace conformal {

MapJacobian jacobianFromDifferences(const glm::dvec3& display, const glm::dvec3& displayDs,
                                    const glm::dvec3& displayDt, const glm::dvec3& scene,
                                    const glm::dvec3& sceneDs, const glm::dvec3& sceneDt) {
    // Keep only the tangential parts (finite differences of unit vectors leave a small normal
    // component).
    const glm::dvec3 ds = displayDs - glm::dot(displayDs, display) * display;
    const glm::dvec3 dt = displayDt - glm::dot(displayDt, display) * display;
    const glm::dvec3 fs = sceneDs - glm::dot(sceneDs, scene) * scene;
    const glm::dvec3 ft = sceneDt - glm::dot(sceneDt, scene) * scene;
    // First fundamental forms on both sides; sigma^2 are the eigenvalues of D^-1 S.
    const double d11 = glm::dot(ds, ds), d12 = glm::dot(ds, dt), d22 = glm::dot(dt, dt);
    const double s11 = glm::dot(fs, fs), s12 = glm::dot(fs, ft), s22 = glm::dot(ft, ft);
    const double detD = d11 * d22 - d12 * d12;
    const double detS = s11 * s22 - s12 * s12;
    MapJacobian j;
    if (!(detD > 0.0)) return j;
    const double trace = (s11 * d22 + s22 * d11 - 2.0 * s12 * d12) / detD;  // tr(D^-1 S)
    const double product = std::max(detS, 0.0) / detD;                       // det(D^-1 S)
    const double discriminant = std::sqrt(std::max(trace * trace - 4.0 * product, 0.0));
    const double largest = 0.5 * (trace + discriminant);
    const double smallest = std::max(0.5 * (trace - discriminant), 0.0);
    j.scale = std::pow(product, 0.25);
    j.quasiConformal = smallest > 0.0 ? std::sqrt(largest / smallest) : INFINITY;
    const double displayArea = glm::dot(glm::cross(ds, dt), display);
    const double sceneArea = glm::dot(glm::cross(fs, ft), scene);
    j.orientation = displayArea * sceneArea > 0.0 ? 1.0 : -1.0;
    return j;
}

std::vector<MapJacobian> cubeMapJacobians(const CubeMap& map) {
    const int n = map.size;
    std::vector<MapJacobian> jacobians(static_cast<std::size_t>(6) * n * n);
    auto sceneAt = [&](int face, int i, int j) {
        const float* p = &map.rgba[map.texelIndex(face, i, j)];
        return glm::dvec3(p[0], p[1], p[2]);
    };
    for (int face = 0; face < 6; ++face) {
        for (int j = 0; j < n; ++j) {
            for (int i = 0; i < n; ++i) {
                const int i0 = std::max(i - 1, 0), i1 = std::min(i + 1, n - 1);
                const int j0 = std::max(j - 1, 0), j1 = std::min(j + 1, n - 1);
                const auto dirAt = [&](int a, int b) {
                    return directionFromCubeFace(face, (a + 0.5) / n, (b + 0.5) / n);
                };
                const glm::dvec3 display = dirAt(i, j);
                const glm::dvec3 scene = glm::normalize(sceneAt(face, i, j));
                jacobians[(static_cast<std::size_t>(face) * n + j) * n + i] = jacobianFromDifferences(
                    display, (dirAt(i1, j) - dirAt(i0, j)) / double(i1 - i0),
                    (dirAt(i, j1) - dirAt(i, j0)) / double(j1 - j0), scene,
                    (sceneAt(face, i1, j) - sceneAt(face, i0, j)) / double(i1 - i0),
                    (sceneAt(face, i, j1) - sceneAt(face, i, j0)) / double(j1 - j0));
            }
        }
    }
    return jacobians;
}

DistortionStatistics distortionStatistics(const CubeMap& map, double cornerExclusionDegrees) {
    const int n = map.size;
    const auto jacobians = cubeMapJacobians(map);
    std::vector<glm::dvec3> corners;
    for (const int corner : boundaryCorners(map.box)) corners.push_back(boxCornerDirection(map.box, corner));
    const double cosExclusion = std::cos(cornerExclusionDegrees * std::numbers::pi / 180.0);
    std::vector<double> values;
    DistortionStatistics stats;
    stats.minOrientation = 1.0;
    for (int face = 0; face < 6; ++face) {
        for (int j = 0; j < n; ++j) {
            for (int i = 0; i < n; ++i) {
                const glm::dvec3 d = directionFromCubeFace(face, (i + 0.5) / n, (j + 0.5) / n);
                if (isMissingDirection(map.box, d)) continue;
                // A texel whose difference stencil reaches onto the ceiling measures the
                // extension too; leave those out with the corners.
                const double step = 2.0 / n;
                bool isNearCeiling = false;
                for (const double ds : {-step, step}) {
                    isNearCeiling = isNearCeiling ||
                        isMissingDirection(map.box, directionFromCubeFace(face, (i + 0.5) / n + ds, (j + 0.5) / n)) ||
                        isMissingDirection(map.box, directionFromCubeFace(face, (i + 0.5) / n, (j + 0.5) / n + ds));
                }
                bool isNearCorner = false;
                for (const auto& corner : corners) isNearCorner = isNearCorner || glm::dot(d, corner) > cosExclusion;
                if (isNearCorner) continue;
                const MapJacobian& jac = jacobians[(static_cast<std::size_t>(face) * n + j) * n + i];
                if (jac.orientation < 0.0) {
                    ++stats.foldedTexels;
                    stats.minOrientation = -1.0;
                }
                if (!isNearCeiling) values.push_back(jac.quasiConformal);
            }
        }
    }
    stats.texelCount = static_cast<long>(values.size());
    if (values.empty()) return stats;
    double sum = 0.0;
    for (const double v : values) sum += v;
    stats.meanK = sum / static_cast<double>(values.size());
    const std::size_t p99 = std::min(values.size() - 1, static_cast<std::size_t>(0.99 * static_cast<double>(values.size())));
    std::nth_element(values.begin(), values.begin() + p99, values.end());
    stats.p99K = values[p99];
    stats.maxK = *std::max_element(values.begin(), values.end());
    return stats;
}

}  // namespace conformal
