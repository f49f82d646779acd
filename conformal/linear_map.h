/// @brief The non-conformal baseline (the paper's Fig. 9): polar angles from the nadir scaled
/// linearly along each longitude so that the ceiling's edge goes to the zenith.
#pragma once

#include "conformal/cave_box.h"
#include "conformal/direction_map.h"

namespace conformal {

/// With theta the angle from the nadir and lambda the azimuth arg(d_x + i d_z) of a display
/// direction (seen from the map centre), F keeps lambda and sets theta' = pi theta /
/// thetaEdge(lambda), where thetaEdge is the angle from the nadir of the ceiling's edge at
/// that azimuth. Ceiling directions continue the same formula past the zenith.
class LinearMap final : public DirectionMap {
public:
    explicit LinearMap(const CaveBox& box);

    glm::dvec3 sceneFromDisplay(const glm::dvec3& display) const override;
    glm::dvec3 displayFromScene(const glm::dvec3& scene) const override;

    /// Angle from the nadir (radians) of the ceiling edge at azimuth `azimuth`.
    double edgeAngleFromNadir(double azimuth) const;

private:
    CaveBox mBox;
};

}  // namespace conformal
