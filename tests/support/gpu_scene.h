/// @brief A volume on the device with its brick min/max, texture and ray caster, as the GPU
/// tests build it.
#pragma once

#include <utility>

#include "engine/render/raycaster.h"
#include "engine/render/volume_texture.h"
#include "volumes/brick_minmax.h"

namespace testing_support {

struct GpuScene {
    GpuScene(const engine::GpuContext& context, volumes::Volume v)
        : volume(std::move(v)), bricks(volumes::buildBrickMinMax(volume)), texture(context, volume),
          raycaster(context, volume, texture, bricks) {}
    volumes::Volume volume;
    volumes::BrickMinMax bricks;
    engine::VolumeTexture texture;
    engine::Raycaster raycaster;
};

}  // namespace testing_support
