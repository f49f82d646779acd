/// @brief The CAVE's box: validation and the directions of its ceiling corners.
#include "conformal/cave_box.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>

namespace conformal {

CaveBox immersiveCabinBox() {
    CaveBox box;
    box.size = glm::dvec3(2.95, 2.21, 2.95);
    box.mapCentre = glm::dvec3(0.0);
    return box;
}

void validateCaveBox(const CaveBox& box) {
    for (int axis = 0; axis < 3; ++axis) {
        const double extent = box.size[axis];
        if (!std::isfinite(extent) || extent <= 0.0) {
            throw std::invalid_argument("CAVE box: size along axis " + std::to_string(axis) +
                                        " is " + std::to_string(extent) +
                                        " m; expected a positive finite length");
        }
        const double c = box.mapCentre[axis];
        if (!std::isfinite(c) || std::abs(c) >= 0.5 * extent) {
            throw std::invalid_argument("CAVE box: map centre coordinate " + std::to_string(c) +
                                        " on axis " + std::to_string(axis) +
                                        " is not strictly inside the box");
        }
    }
}

std::array<glm::dvec3, 4> ceilingCornerDirections(const CaveBox& box) {
    const glm::dvec3 half = 0.5 * box.size;
    const std::array<glm::dvec3, 4> corners = {
        glm::dvec3(half.x, half.y, half.z), glm::dvec3(-half.x, half.y, half.z),
        glm::dvec3(-half.x, half.y, -half.z), glm::dvec3(half.x, half.y, -half.z)};
    std::array<glm::dvec3, 4> directions{};
    for (int k = 0; k < 4; ++k) directions[k] = glm::normalize(corners[k] - box.mapCentre);
    return directions;
}

bool isCeilingDirection(const CaveBox& box, const glm::dvec3& direction) {
    if (direction.y <= 0.0) return false;
    // Where the ray meets the ceiling plane; it leaves through the ceiling when that point
    // lies within the ceiling's rectangle.
    const double t = (0.5 * box.size.y - box.mapCentre.y) / direction.y;
    const glm::dvec3 hit = box.mapCentre + t * direction;
    return std::abs(hit.x) <= 0.5 * box.size.x && std::abs(hit.z) <= 0.5 * box.size.z;
}

}  // namespace conformal
