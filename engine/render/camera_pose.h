/// @brief Where the viewer is and where it looks: the pose a camera path, a display render, a
/// review page and the studies all speak of.
#pragma once

#include <glm/glm.hpp>

namespace engine {

/// Where the viewer is and where it looks, in volume millimetres (forward and up are unit,
/// orthogonal).
struct CameraPose {
    glm::dvec3 positionMm{0.0};
    glm::dvec3 forward{0.0, 0.0, 1.0};
    glm::dvec3 up{0.0, 1.0, 0.0};
};

}  // namespace engine
