/// @brief The ray caster: renders one image (a wall for one eye, or a pinhole view) of a
/// volume in one compute dispatch, with the features chosen per call.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "engine/core/command_submission.h"
#include "engine/core/compute_pipeline.h"
#include "engine/core/gpu_context.h"
#include "engine/render/gradient_volume.h"
#include "engine/render/render_settings.h"
#include "engine/render/sampled_textures.h"
#include "engine/render/view_rays.h"
#include "engine/render/volume_texture.h"
#include "volumes/brick_minmax.h"

namespace shaders {
struct RaycastUniforms;  // shaders/host_device.h
}

namespace engine {

class Raycaster;

/// Images submitted to the device together (one command buffer) and not yet read back. The host
/// is free while the device works; Raycaster::collect waits and reads the images. Dropping a
/// batch waits for the device and discards its images.
class RenderBatch {
public:
    RenderBatch(RenderBatch&& other) noexcept;
    RenderBatch& operator=(RenderBatch&&) = delete;
    RenderBatch(const RenderBatch&) = delete;
    RenderBatch& operator=(const RenderBatch&) = delete;
    ~RenderBatch();

    [[nodiscard]] std::size_t size() const { return mSlots.size(); }

private:
    friend class Raycaster;
    RenderBatch() = default;

    Raycaster* mOwner = nullptr;
    std::vector<int> mSlots;         // the ray caster's per-image resources in use, one per image
    std::vector<bool> mIsWritingHits;
    std::optional<SubmittedWork> mWork;
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
    /// conformal::CubeMap (6 faces in Vulkan order, size^2 RGBA float each). Not while a batch
    /// is in flight.
    void setCubeMap(int size, std::span<const float> rgba);
    /// Binds the bounds (conformal::speedBoundMap of the cube map set last) by which exact-warped
    /// rays skip empty space when RenderSettings::isSkippingBentRays asks; a new cube map drops
    /// them. Not while a batch is in flight.
    void setSpeedBounds(int size, std::span<const float> rgba);

    /// Renders one image and waits for it. Throws std::invalid_argument for bad rays or
    /// settings, and std::logic_error for a warp without a cube map.
    RenderedImage render(const ViewRays& rays, const RenderSettings& settings, const Warp& warp = {});

    /// Records every request into one command buffer, submits it and returns without waiting,
    /// so the host can work (encode the previous frame's images, say) while the device renders.
    /// At most kMaxImagesInFlight images may be submitted and not yet collected. Throws like
    /// render() before anything is submitted.
    RenderBatch submit(std::span<const RenderRequest> requests);
    /// Waits for the batch and reads its images back, in the order they were requested; the
    /// pixels equal render()'s for the same request.
    std::vector<RenderedImage> collect(RenderBatch& batch);

    /// Images that may be in flight at once: two stereo frames of a six-wall display with their
    /// before/after walls.
    static constexpr int kMaxImagesInFlight = 48;
    /// Chord and polyline tables held now (one per display geometry and warp rendered).
    [[nodiscard]] std::size_t chordTableCount() const { return mChordTables.size(); }
    /// Memory the kept tables may take, by default 1.5 GiB (the chord's 32 bytes a pixel, the
    /// polyline's 64, and 16 a tile: the 5-wall cabin's stereo walls at full size take 453 MB of
    /// chords, 906 MB of polylines, the centre eye's chords for --before-after 227 MB more). A
    /// geometry past it gets its table filled anew for each frame: the same images, at the cost
    /// of the fill.
    void setChordTableBudget(std::uint64_t bytes);

private:
    friend class RenderBatch;
    struct Targets;
    struct Slot;
    /// What one request records besides its own dispatch: the chord table it reads, if any,
    /// and whether it fills it first, from `canonical`: the request's rays in CAVE axes about a
    /// map centre at the origin, as the table's key holds them.
    struct ChordTableUse {
        const GpuBuffer* table = nullptr;
        bool isFilling = false;
        RenderRequest canonical;
        double canonicalReachMm = 0.0;
    };
    using PipelineKey = std::tuple<int, int, int, int, int, int, int, int, int, int, int, int, int>;

    void validateRequest(const RenderRequest& request) const;
    void recordRequest(const vk::raii::CommandBuffer& commands, const RenderRequest& request, int slotIndex,
                       ChordTableUse chordTable);
    ChordTableUse chordTableFor(const RenderRequest& request, int slotIndex);
    /// The volume's box in volume millimetres: its lower and upper corners.
    std::pair<glm::dvec3, glm::dvec3> volumeBoxMm() const;
    /// How far beyond the near plane a chord's far end lies (see raycast.comp).
    double chordReachMm(const glm::dvec3& mapCentreMm) const;
    /// The uniforms' far reach for `warp`: the chord's, or for exact mode the farthest corner.
    double chordReachFor(const Warp& warp) const;
    shaders::RaycastUniforms uniformsFor(const RenderRequest& request, const TransferTable& table,
                                         double farReachMm) const;
    void bindResources(ComputePipeline& pipeline, uint32_t set, const GpuBuffer& uniforms, const GpuImage& color,
                       const GpuImage& hit, const SampledTexture& skipDistance, const SampledTexture& transfer,
                       const SampledTexture& gradientVolume, const GpuBuffer& chordTable,
                       const GpuBuffer& rayStarts) const;
    void releaseSlots(const std::vector<int>& slots);

    ComputePipeline& pipelineFor(const RenderSettings& settings, WarpMode warp, int chordTable, int rayStart);
    /// The tile pass's pipeline for a request's rays: only the ray construction matters to it.
    /// (With CVC_CHORD_TABLE_FILL: the pass that writes the chord table's cone bounds.)
    ComputePipeline& rayStartFillPipelineFor(WarpMode warp, int chordTable);
    const SampledTexture& skipDistanceFor(const RenderSettings& settings);
    /// The gradient volume where `settings` ask for it, computed on first use; null where they do
    /// not, or where the device could not hold it (the shader then takes the volume's taps).
    const SampledTexture* gradientVolumeFor(const RenderSettings& settings);
    /// The table of the preset `name`, tabulated on first use.
    const TransferTable& transferTableFor(const std::string& name);
    static std::string transferNameOf(const RenderSettings& settings);
    /// The texture a request samples: its preset's table, corrected for a fixed step.
    const SampledTexture& transferTextureFor(const RenderSettings& settings);
    /// The base step in millimetres: settings' voxels times the smallest spacing.
    double baseStepMm(const RenderSettings& settings) const;

    const GpuContext* mContext;
    const volumes::Volume* mVolumeData;
    const VolumeTexture* mVolume;
    const volumes::BrickMinMax* mBricks;
    std::map<int, volumes::BrickMinMax> mFinerCells;  // by cell size
    SampledTexture mCubeMap;
    bool mHasCubeMap = false;
    SampledTexture mSpeedBounds;  // conformal::speedBoundMap of the cube map: the exact warp's skips
    bool mHasSpeedBounds = false;
    /// By content, each made on the first request that shades with it (both only where requests
    /// mix them, as benchmarks do; an in-flight batch may still read the other).
    std::map<GradientVolumeContent, SampledTexture> mGradientVolumes;
    bool mIsGradientVolumeTooLarge = false;  // the device could not hold one: taps instead
    SampledTexture mNoGradientVolume;               // bound where no gradient volume is read
    std::map<PipelineKey, std::unique_ptr<ComputePipeline>> mPipelines;
    std::map<std::string, SampledTexture> mSkipDistances;    // by cell size and "iso:<value>" or "tf:<name>"
    std::map<std::string, SampledTexture> mTransferTextures;  // by preset name, and step where corrected
    std::map<std::string, TransferTable> mTransferTables;
    std::vector<std::unique_ptr<Slot>> mSlots;  // per-image uniforms, timers and targets
    std::vector<bool> mIsSlotBusy;
    GpuImage mNoHitImage;  // bound where hits are not asked for (the shader then never writes it)
    // Chord tables by display geometry (quantised, in CAVE axes about the map centre), dropped
    // when the cube map changes; past the byte budget, a frame fills its slot's own table.
    std::map<std::vector<long long>, std::unique_ptr<GpuBuffer>> mChordTables;
    vk::DeviceSize mChordTableBytes = 0;
    std::uint64_t mChordTableBudgetBytes = std::uint64_t{3} << 29;
    GpuBuffer mNoChordTable;  // bound where no table is read or written
    GpuBuffer mNoRayStarts;   // bound where the tile pass does not run
};

}  // namespace engine
