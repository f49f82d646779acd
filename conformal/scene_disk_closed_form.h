/// @brief The closed form of the scene-side Riemann map phi6 for a square ceiling centred above
/// the map centre (DESIGN.md, "The map"): the independent oracle for the Ricci-flow phi6.
#pragma once

#include <complex>

#include <glm/vec3.hpp>

#include "conformal/cave_box.h"

namespace conformal {

/// True when the closed form applies: a square ceiling (width == depth) centred above the map
/// centre (mapCentre.x == mapCentre.z == 0).
bool hasSceneDiskClosedForm(const CaveBox& box);

/// phi6 of a unit scene direction, aligned like the computed map (corners 0, 1, 2 at 1, i, -1):
/// with w = (d_x + i d_z) / (1 - d_y), a = |w(corner)|^4,
/// phi6(w) = e^{-i pi/4} w / (a^{1/4} sqrt(1 + sqrt(1 + w^4 / a))), principal roots. The branch
/// cut of the inner root lies on the slit X, so directions exactly on it take either side.
std::complex<double> sceneDiskFromDirectionClosedForm(const CaveBox& box, const glm::dvec3& direction);

/// The inverse: a point of the closed unit disk to the unit scene direction,
/// w = (4a)^{1/4} z / sqrt(1 - z^4) with z = e^{i pi/4} zeta, then inverse stereographic
/// projection from the zenith.
glm::dvec3 directionFromSceneDiskClosedForm(const CaveBox& box, std::complex<double> zeta);

}  // namespace conformal
