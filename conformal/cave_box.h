/// @brief The CAVE's box and the point the map is centred on, with the directions of its corners.
#pragma once

#include <array>

#include <glm/vec3.hpp>

namespace conformal {

/// An axis-aligned display box in CAVE space (right-handed, metres, y up), centred at the origin:
/// it spans [-size/2, +size/2] on each axis. The ceiling (+y) is the missing wall. The conformal
/// map is centred on `mapCentre`, a point strictly inside the box.
struct CaveBox {
    glm::dvec3 size{2.4, 2.4, 2.4};  ///< width (x), height (y), depth (z) in metres
    glm::dvec3 mapCentre{0.0};       ///< centre of the sphere of directions, CAVE space, metres
};

/// The Immersive Cabin: four 2.95 m x 2.21 m walls on a 2.95 m square floor, centred.
CaveBox immersiveCabinBox();

/// Throws std::invalid_argument unless every size is positive and finite and the map centre
/// lies strictly inside the box.
void validateCaveBox(const CaveBox& box);

/// Unit directions from the map centre to the four ceiling corners, in counter-clockwise order
/// of azimuth arg(x + i z): k = 0 is (+x, +z), 1 is (-x, +z), 2 is (-x, -z), 3 is (+x, -z).
std::array<glm::dvec3, 4> ceilingCornerDirections(const CaveBox& box);

/// True when the ray from the map centre along `direction` leaves the box through the closed
/// ceiling face, i.e. the direction is outside the display domain Omega5.
bool isCeilingDirection(const CaveBox& box, const glm::dvec3& direction);

}  // namespace conformal
