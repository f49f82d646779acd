/// @brief The ray caster: renders one image (a wall for one eye, or a pinhole view) of a
/// volume in one compute dispatch, with the features chosen per call.
#pragma once

#include <map>
#include <memory>
#include <span>
#include <string>
#include <tuple>
#include <vector>

#include "engine/compute_pipeline.h"
#include "engine/gpu_context.h"
#include "engine/sampled_textures.h"
#include "engine/view_rays.h"
#include "engine/volume_texture.h"
#include "volumes/brick_minmax.h"

namespace engine {

enum class RenderMode { IsoSurface, Composite };
enum class VolumeFilter { Trilinear, Tricubic };
/// How rays are bent: not at all; by mapping a ray's near and far points and marching the
/// chord between them (paper Eq. 7, exact for an eye at the map centre); or by mapping every
/// sample (the reference the chord is measured against for stereo eyes).
enum class WarpMode { None, Chord, Exact };

struct RenderSettings {
    RenderMode mode = RenderMode::IsoSurface;
    double isoHu = -500.0;                        // iso-surface mode: the air / soft-tissue boundary
    std::string transferFunction = "colon-wall";  // composite mode: a preset name
    double stepVoxels = 0.5;                      // base step, in units of the smallest voxel side
    int refinementSteps = 6;                      // iso mode: bisection steps; 0 = the raw sample
    VolumeFilter filter = VolumeFilter::Trilinear;
    bool isSkipping = true;                       // empty-space skipping over a distance map
    int skipCellVoxels = 2;                       // cell edge of that map, voxels (8: the 8^3 bricks)
    bool isAdaptive = false;                      // lengthen steps where a pixel covers > 1 voxel
    double minStepVoxels = 0.25;                  // adaptive step bounds
    double maxStepVoxels = 4.0;
    double earlyTerminationOpacity = 0.98;        // composite mode
    bool isJittered = false;                      // offset each ray's start by a hashed fraction
    uint32_t jitterSeed = 0;
    double lightHalfDistanceMm = 0.0;             // the headlight is half as bright here; 0: no falloff
    double roughness = 0.45;                      // Cook-Torrance
    double fresnel = 0.04;
    double ambient = 0.10;
    bool isWritingHits = true;                    // fill RenderedImage::hitMm
    bool isCountingFetches = false;               // benchmarks: hitMm's w = volume fetches per ray
};

/// The warp of space about the map centre (DESIGN.md "Rays"), in volume millimetres.
struct Warp {
    WarpMode mode = WarpMode::None;
    glm::dvec3 mapCentreMm{0.0};
    glm::dmat3 caveToVolume{1.0};  // columns: the CAVE's x, y, z axes as unit volume vectors
};

/// One rendered image: 8-bit RGBA colour and, per pixel, the first-hit position in volume
/// millimetres (xyz) with w = 1 for a hit, 0 for a miss. Row 0 is the top of the image.
/// Composite mode's hit is where the accumulated opacity first reaches 0.5.
struct RenderedImage {
    int width = 0;
    int height = 0;
    std::vector<uint8_t> rgba;
    std::vector<float> hitMm;  // 4 floats per pixel; empty when hits were not asked for
    double deviceMs = -1.0;    // time of the ray-casting dispatch on the device; < 0: unknown
};

/// Holds the volume's textures, the pipelines (one per feature combination, built on first
/// use), the empty-space maps (one per iso value or transfer function and cell size) and the
/// output images, so the walls, eyes and frames of a sequence share them.
class Raycaster {
public:
    /// `volume` is the CPU copy of what `texture` holds (finer skipping cells are built from
    /// it); `bricks` its 8^3 brick min/max, used as is for 8-voxel cells (e.g. from .vdb leaves).
    /// Both must outlive the ray caster.
    Raycaster(const GpuContext& context, const volumes::Volume& volume, const VolumeTexture& texture,
              const volumes::BrickMinMax& bricks);
    ~Raycaster();

    /// Binds the baked map that WarpMode::Chord and ::Exact bend rays with: the texels of a
    /// conformal::CubeMap (6 faces in Vulkan order, size^2 RGBA float each).
    void setCubeMap(int size, std::span<const float> rgba);

    /// Throws std::invalid_argument for bad rays or settings, and std::logic_error for a warp
    /// without a cube map.
    RenderedImage render(const ViewRays& rays, const RenderSettings& settings, const Warp& warp = {});

private:
    struct Targets;
    using PipelineKey = std::tuple<int, int, int, int, int, int>;

    ComputePipeline& pipelineFor(const RenderSettings& settings, WarpMode warp);
    const SampledTexture& skipDistanceFor(const RenderSettings& settings);
    const SampledTexture& transferTextureFor(const std::string& name);

    const GpuContext* mContext;
    const volumes::Volume* mVolumeData;
    const VolumeTexture* mVolume;
    const volumes::BrickMinMax* mBricks;
    std::map<int, volumes::BrickMinMax> mFinerCells;  // by cell size
    GpuBuffer mUniforms;
    SampledTexture mCubeMap;
    bool mHasCubeMap = false;
    std::map<PipelineKey, std::unique_ptr<ComputePipeline>> mPipelines;
    std::map<std::string, SampledTexture> mSkipDistances;    // by cell size and "iso:<value>" or "tf:<name>"
    std::map<std::string, SampledTexture> mTransferTextures;  // by preset name
    std::map<std::string, TransferTable> mTransferTables;
    std::map<std::pair<int, int>, std::unique_ptr<Targets>> mTargets;  // by image size
};

}  // namespace engine
