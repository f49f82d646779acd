/// @brief The warp tests' scene: a ball of air in tissue (volumes::makeBallPhantom) on the
/// device, seen from inside on the 5-wall cube (the 6-wall CAVE without its ceiling) through the
/// conformal map, in iso mode between the air and the tissue.
#pragma once

#include <algorithm>
#include <vector>

#include "engine/display/display.h"
#include "engine/render/render_settings.h"
#include "tests/support/gpu_scene.h"
#include "volumes/analytic_phantom.h"

namespace testing_support {

/// A ball of air in tissue on the device: every ray from inside ends on its sphere.
struct BallRoom : GpuScene {
    BallRoom(const engine::GpuContext& context, const volumes::BallSpec& spec)
        : GpuScene(context, volumes::makeBallPhantom(spec)) {}
};

/// The 6-wall CAVE without its ceiling, every wall `pixels` square, through the conformal map.
inline engine::Display fiveWallCube(int pixels) {
    engine::Display display = engine::displayPreset("cave6");
    display.walls.pop_back();  // no ceiling
    for (auto& wall : display.walls) wall.width = wall.height = pixels;
    display.map = conformal::MapKind::Conformal;
    return display;
}

/// Iso mode halfway between the room's air (-1000 HU) and its tissue (40 HU), half-voxel steps.
inline engine::RenderSettings ballRoomSettings() {
    engine::RenderSettings settings;
    settings.isoHu = -480.0;
    settings.stepVoxels = 0.5;
    return settings;
}

/// The value of `values` at `fraction` of the way through their sorted order (nearest rank
/// below); 0 for none.
inline double percentile(std::vector<double> values, double fraction) {
    if (values.empty()) return 0.0;
    std::sort(values.begin(), values.end());
    return values[static_cast<std::size_t>(fraction * static_cast<double>(values.size() - 1))];
}

}  // namespace testing_support
