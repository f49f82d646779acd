/// @brief Renders the first crossing of an iso value through a pinhole camera on the device.
#pragma once

#include <memory>
#include <vector>

#include "engine/compute_pipeline.h"
#include "engine/gpu_context.h"
#include "engine/pinhole_camera.h"
#include "engine/volume_texture.h"

namespace engine {

struct IsoSurfaceSettings {
    double isoHu = -500.0;      // the air / soft-tissue boundary of CT colonography
    double stepVoxels = 0.5;    // march step, in units of the smallest voxel spacing
    int bisectionSteps = 6;     // refinement of the crossing between two samples
};

/// One rendered image: 8-bit RGBA colour and, per pixel, the first-hit position in volume
/// millimetres (xyz) with w = 1 for a hit and 0 for a miss. Row 0 is the top of the image.
struct RenderedImage {
    int width = 0;
    int height = 0;
    std::vector<uint8_t> rgba;
    std::vector<float> hitMm;  // 4 floats per pixel
    double deviceMs = -1.0;    // time of the ray-casting dispatch on the device; < 0: unknown
};

/// Holds the pipeline and the per-size output images, so repeated renders reuse them.
class IsoSurfaceRenderer {
public:
    IsoSurfaceRenderer(const GpuContext& context, const VolumeTexture& volume);
    ~IsoSurfaceRenderer();

    /// Throws std::invalid_argument for a bad camera or settings.
    RenderedImage render(const PinholeCamera& camera, const IsoSurfaceSettings& settings);

private:
    struct Targets;
    const GpuContext* mContext;
    const VolumeTexture* mVolume;
    ComputePipeline mPipeline;
    GpuBuffer mUniforms;
    std::unique_ptr<Targets> mTargets;
};

}  // namespace engine
