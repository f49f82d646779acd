/// @brief The interface both maps of the sphere of directions share: the conformal map and the
/// linear baseline.
#pragma once

#include <glm/vec3.hpp>

namespace conformal {

/// A map between display directions (where light leaves a wall toward the viewer at the map
/// centre) and scene directions (what that pixel shows), unit vectors in CAVE space.
class DirectionMap {
public:
    virtual ~DirectionMap() = default;
    /// F: display direction -> scene direction. Defined on Omega5; ceiling directions get the
    /// map's smooth extension (only texture filtering at the ceiling edges ever sees them).
    virtual glm::dvec3 sceneFromDisplay(const glm::dvec3& display) const = 0;
    /// G = F^-1: scene direction -> display direction in Omega5.
    virtual glm::dvec3 displayFromScene(const glm::dvec3& scene) const = 0;
};

}  // namespace conformal
