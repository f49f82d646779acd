/// @brief The non-conformal baseline (the paper's Fig. 9): polar angles from the nadir scaled
/// linearly along each longitude so that the ceiling's edge goes to the zenith.
#pragma once

#include "conformal/cave_box.h"
#include "conformal/direction_map.h"

namespace conformal {

/// With theta the angle from the nadir and lambda the azimuth arg(d_x + i d_z) of a display
/// direction (seen from the map centre), F keeps lambda and sets theta' = pi theta /
/// thetaEdge(lambda), where thetaEdge is the angle from the nadir at which that longitude first
/// leaves the display: the ceiling's edge for the cabin; toward a missing wall, the floor's edge
/// below it. Missing directions continue the same formula past the zenith. Needs the floor
/// (the constructor throws std::invalid_argument without it).
class LinearMap final : public DirectionMap {
public:
    explicit LinearMap(const CaveBox& box);

    glm::dvec3 sceneFromDisplay(const glm::dvec3& display) const override;
    glm::dvec3 displayFromScene(const glm::dvec3& scene) const override;

    /// Angle from the nadir (radians) at which the longitude at `azimuth` leaves the display.
    double edgeAngleFromNadir(double azimuth) const;

private:
    CaveBox mBox;
};

}  // namespace conformal
