/// @brief The Python module's Vulkan side: one device for the whole interpreter, made on first
/// use and reused by every call, and per volume its texture and ray caster, made on its first
/// render and kept while the volume lives.
#pragma once

#include <memory>
#include <string>

#include "engine/core/gpu_context.h"
#include "engine/render/raycaster.h"
#include "engine/render/volume_texture.h"
#include "volumes/load_volume.h"

namespace cvc_python {

/// The device every render of this process uses: the one $CVC_DEVICE names, else the best.
std::shared_ptr<engine::GpuContext> sharedContext();

/// A volume as Python holds it: the voxels (int16 HU), their brick min/max for skipping, and
/// once rendered its texture and ray caster on the shared device.
class SessionVolume {
public:
    SessionVolume(volumes::LoadedVolume loaded, std::string source);
    ~SessionVolume();

    [[nodiscard]] const volumes::Volume& volume() const { return mLoaded.volume; }
    [[nodiscard]] const volumes::LoadedVolume& loaded() const { return mLoaded; }
    [[nodiscard]] const std::string& source() const { return mSource; }
    /// The ray caster of this volume (made on first use). `cubeMapKey` names the display map
    /// set on it last, so a render of the same display does not upload the map again.
    engine::Raycaster& raycaster();
    std::string cubeMapKey;

private:
    volumes::LoadedVolume mLoaded;
    std::string mSource;
    // Declared in the order they are made; destroyed in reverse, the device last.
    std::shared_ptr<engine::GpuContext> mContext;
    std::unique_ptr<engine::VolumeTexture> mTexture;
    std::unique_ptr<engine::Raycaster> mRaycaster;
};

}  // namespace cvc_python
