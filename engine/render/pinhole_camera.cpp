#include "engine/render/pinhole_camera.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace engine {
namespace {

bool isFinite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace

CameraBasis cameraBasis(const PinholeCamera& camera) {
    if (camera.width < 1 || camera.height < 1 || camera.width > kMaxImageSide || camera.height > kMaxImageSide) {
        throw std::invalid_argument("camera: image size " + std::to_string(camera.width) + "x" +
                                    std::to_string(camera.height) + " is outside 1.." + std::to_string(kMaxImageSide));
    }
    if (!(camera.verticalFovDeg > 0.0 && camera.verticalFovDeg < 179.0)) {
        throw std::invalid_argument("camera: vertical field of view " + std::to_string(camera.verticalFovDeg) +
                                    " degrees is outside (0, 179)");
    }
    if (!isFinite(camera.positionMm) || !isFinite(camera.lookAtMm) || !isFinite(camera.up)) {
        throw std::invalid_argument("camera: position, look-at and up must be finite");
    }
    const glm::dvec3 view = camera.lookAtMm - camera.positionMm;
    if (glm::length(view) < 1e-9) throw std::invalid_argument("camera: look-at point equals the camera position");
    const glm::dvec3 forward = glm::normalize(view);
    const glm::dvec3 rightUnnormalised = glm::cross(forward, camera.up);
    if (glm::length(rightUnnormalised) < 1e-9 * std::max(1.0, glm::length(camera.up))) {
        throw std::invalid_argument("camera: up vector is zero or parallel to the view direction");
    }
    const glm::dvec3 right = glm::normalize(rightUnnormalised);
    const glm::dvec3 up = glm::cross(right, forward);
    const double tanHalfY = std::tan(glm::radians(camera.verticalFovDeg) * 0.5);
    const double aspect = static_cast<double>(camera.width) / camera.height;
    return {forward, right * (tanHalfY * aspect), up * tanHalfY};
}

glm::dvec3 rayDirection(const PinholeCamera& camera, double column, double row) {
    const CameraBasis basis = cameraBasis(camera);
    const double x = (column + 0.5) / camera.width * 2.0 - 1.0;
    const double y = 1.0 - (row + 0.5) / camera.height * 2.0;
    return glm::normalize(basis.forward + x * basis.rightScaled + y * basis.upScaled);
}

}  // namespace engine
