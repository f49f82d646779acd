/// @brief A pinhole camera in volume millimetres and the rays it shoots through its pixels.
#pragma once

#include <glm/glm.hpp>

namespace engine {

struct PinholeCamera {
    glm::dvec3 positionMm{0.0};
    glm::dvec3 lookAtMm{0.0, 0.0, -1.0};
    glm::dvec3 up{0.0, 1.0, 0.0};
    double verticalFovDeg = 45.0;  // full opening angle between the top and bottom image edges
    int width = 512;
    int height = 512;
};

/// The camera frame, scaled so that the ray through image point (x, y) in [-1, 1]^2
/// (x right, y up) has direction forward + x * rightScaled + y * upScaled.
struct CameraBasis {
    glm::dvec3 forward;
    glm::dvec3 rightScaled;
    glm::dvec3 upScaled;
};

/// Largest image side accepted (pixels).
inline constexpr int kMaxImageSide = 16384;

/// Throws std::invalid_argument naming the field for a camera that cannot be rendered (size,
/// field of view, position equal to look-at, up parallel to the view, non-finite values).
CameraBasis cameraBasis(const PinholeCamera& camera);

/// Unit direction of the ray through the centre of pixel (column, row), row 0 at the top:
/// the C++ twin of the ray setup in shaders/raycast_iso.comp.
glm::dvec3 rayDirection(const PinholeCamera& camera, double column, double row);

}  // namespace engine
