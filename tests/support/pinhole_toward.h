/// @brief A square pinhole camera looking from one point at another, as the ray-caster tests aim
/// it: up is +z unless the view runs nearly along z, then +y.
#pragma once

#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "engine/render/pinhole_camera.h"

namespace testing_support {

inline engine::PinholeCamera cameraToward(const glm::dvec3& position, const glm::dvec3& lookAt, double fovDeg,
                                          int size) {
    engine::PinholeCamera camera;
    camera.positionMm = position;
    camera.lookAtMm = lookAt;
    camera.up = std::abs(glm::normalize(lookAt - position).z) > 0.9 ? glm::dvec3(0, 1, 0) : glm::dvec3(0, 0, 1);
    camera.verticalFovDeg = fovDeg;
    camera.width = camera.height = size;
    return camera;
}

}  // namespace testing_support
