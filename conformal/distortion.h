/// @brief Distortion of a direction map measured by finite differences: the quasi-conformal
/// ratio K = sigma_max / sigma_min, the local scale sqrt(sigma_max sigma_min) and orientation.
#pragma once

#include <vector>

#include <glm/vec3.hpp>

#include "conformal/cube_map.h"

namespace conformal {

/// The Jacobian of a map of the sphere at one point, from the tangent vectors of a
/// parametrisation of the display sphere and of their images.
struct MapJacobian {
    double scale = 0.0;           ///< sqrt(sigma_max sigma_min): scene radians per display radian
    double quasiConformal = 0.0;  ///< K = sigma_max / sigma_min >= 1; 1 for a conformal map
    double orientation = 0.0;     ///< sign of det dF: +1 preserves orientation, -1 folds over
};

/// From display direction d with tangents dd/ds, dd/dt and scene direction F(d) with dF/ds,
/// dF/dt (any common parameters s, t).
MapJacobian jacobianFromDifferences(const glm::dvec3& display, const glm::dvec3& displayDs,
                                    const glm::dvec3& displayDt, const glm::dvec3& scene,
                                    const glm::dvec3& sceneDs, const glm::dvec3& sceneDt);

/// Per texel of `map`: the Jacobian by differences of the stored scene directions with the
/// neighbouring texels of the same face (central inside, one-sided on the face's border).
std::vector<MapJacobian> cubeMapJacobians(const CubeMap& map);

/// Statistics over the texels whose direction lies in the display domain (Omega5 for the cabin)
/// and more than `cornerExclusionDegrees` from every corner of its boundary (boundaryCorners):
/// fold-overs over all of them, K over those whose difference stencil (two texels each way)
/// stays off the missing walls.
struct DistortionStatistics {
    double meanK = 0.0;
    double p99K = 0.0;
    double maxK = 0.0;
    double minOrientation = 0.0;  ///< -1 if any counted texel folds over
    long foldedTexels = 0;
    long texelCount = 0;
};
DistortionStatistics distortionStatistics(const CubeMap& map, double cornerExclusionDegrees);

}  // namespace conformal
