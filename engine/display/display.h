/// @brief Immersive displays placed in a volume: the rays of one wall for one eye once the CAVE
/// sits in the volume. The display itself (walls, box, eyes, presets) is display_description.h.
#pragma once

#include <glm/glm.hpp>

#include "engine/display/display_description.h"
#include "engine/render/raycaster.h"
#include "engine/render/view_rays.h"

namespace engine {

/// Where the CAVE sits in a volume: its map centre (Display::mapCentreM) at `positionMm`, its
/// front (-z) looking along `forward`, its up (+y) along `up` (both in volume axes), and
/// `mmPerMetre` volume millimetres for each CAVE metre (a colon lumen of ~40 mm fills a CAVE
/// of ~3 m at ~15).
struct ScenePose {
    glm::dvec3 positionMm{0.0};
    glm::dvec3 forward{0.0, 0.0, 1.0};
    glm::dvec3 up{0.0, -1.0, 0.0};
    double mmPerMetre = 20.0;
};

/// The rotation taking CAVE axes to volume axes (columns: CAVE x, y, z). Throws
/// std::invalid_argument for a zero or parallel forward and up.
glm::dmat3 caveToVolumeRotation(const ScenePose& pose);

/// The rays of `wall` seen by `eye` with the CAVE placed by `pose`, and the warp that the
/// display's map asks for (WarpMode::None for MapKind::None; else `warpMode`), bending about
/// the map centre; WarpMode::EyeCentred becomes a chord bending about the eye itself.
struct WallView {
    ViewRays rays;
    Warp warp;
};
WallView wallView(const Display& display, WallName wall, Eye eye, const ScenePose& pose, WarpMode warpMode);

}  // namespace engine
