#include "engine/render/raycaster.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>
#include <stdexcept>

#include "conformal/cube_map_speed.h"
#include "engine/core/command_submission.h"
#include "engine/render/empty_space_map.h"
#include "engine/render/gradient_volume.h"
#include "host_device.h"
#include "raycast_spv.h"

namespace engine {

// Every member's offset is compared with the compiled shader's reflection by a test
// (tests/engine/uniform_layout_test.cpp); this catches a struct that no longer fills its slots.
static_assert(sizeof(shaders::RaycastUniforms) == 18 * 16, "RaycastUniforms must be 18 16-byte slots (std140)");

namespace {

/// The ray caster's bindings (shaders/host_device.h) and their descriptor types, in one place.
constexpr std::pair<uint32_t, vk::DescriptorType> kRaycastBindings[] = {
    {CVC_BINDING_UNIFORMS, vk::DescriptorType::eUniformBuffer},
    {CVC_BINDING_VOLUME, vk::DescriptorType::eCombinedImageSampler},
    {CVC_BINDING_COLOR_IMAGE, vk::DescriptorType::eStorageImage},
    {CVC_BINDING_HIT_IMAGE, vk::DescriptorType::eStorageImage},
    {CVC_BINDING_SKIP_DISTANCE, vk::DescriptorType::eCombinedImageSampler},
    {CVC_BINDING_TRANSFER_FUNCTION, vk::DescriptorType::eCombinedImageSampler},
    {CVC_BINDING_CUBE_MAP, vk::DescriptorType::eCombinedImageSampler},
    {CVC_BINDING_CHORD_TABLE, vk::DescriptorType::eStorageBuffer},
    {CVC_BINDING_RAY_START, vk::DescriptorType::eStorageBuffer},
    {CVC_BINDING_SPEED_BOUND, vk::DescriptorType::eCombinedImageSampler},
    {CVC_BINDING_GRADIENT_VOLUME, vk::DescriptorType::eCombinedImageSampler},
};

/// The descriptor types by binding number, as ComputePipeline takes them.
std::vector<vk::DescriptorType> raycastDescriptorTypes() {
    std::vector<vk::DescriptorType> types(std::size(kRaycastBindings));
    for (const auto& [binding, type] : kRaycastBindings) types.at(binding) = type;
    return types;
}

/// Whether a request's march starts where the tile pass says: with skipping, whose distance map
/// the pass reads, and with straight segments (the exact warp bends every sample); a polyline's
/// pieces only with the chord table, where the tile's bound was measured once (ray_start.glsl).
bool usesRayStartPass(const RenderRequest& request, bool hasChordTable) {
    const WarpMode warp = request.warp.mode;
    return request.settings.isSkipping && request.settings.isUsingRayStartPass && warp != WarpMode::Exact &&
           (warp != WarpMode::Polyline || hasChordTable);
}

/// The request as it is rendered: a polyline for an eye at the map centre is one chord (its ray
/// is not bent), so it takes the chord's smaller table and the same pixels.
RenderRequest effectiveRequest(const RenderRequest& request) {
    RenderRequest effective = request;
    if (request.warp.mode == WarpMode::Polyline && glm::length(request.rays.eyeMm - request.warp.mapCentreMm) < 1e-9) {
        effective.warp.mode = WarpMode::Chord;
    }
    return effective;
}

int32_t warpIdOf(WarpMode warp) {
    switch (warp) {
        case WarpMode::None: return CVC_WARP_NONE;
        case WarpMode::Chord: return CVC_WARP_CHORD;
        case WarpMode::Polyline: return CVC_WARP_POLYLINE;
        case WarpMode::Exact: return CVC_WARP_EXACT;
        case WarpMode::EyeCentred: break;  // the display code makes it a chord (validateRequest)
    }
    throw std::invalid_argument("unknown warp mode");
}

/// Bytes of a chord (or polyline) table per tile of the image.
vk::DeviceSize tableBytesPerTile(WarpMode warp) {
    return warp == WarpMode::Polyline ? CVC_POLYLINE_TABLE_BYTES_PER_TILE : CVC_CHORD_TABLE_BYTES_PER_TILE;
}

uint32_t tilesAlong(int pixels) { return static_cast<uint32_t>((pixels + CVC_TILE_SIZE - 1) / CVC_TILE_SIZE); }

/// The settings of the passes that only build rays (the chord-table fill and the tile pass): the
/// defaults serve (skipping on, fixed step, no counting), without the gradient volume, since
/// nothing is shaded.
RenderSettings rayPassSettings() {
    RenderSettings settings;
    settings.isUsingGradientVolume = false;
    return settings;
}

}  // namespace

/// Output images and their readback buffers for one image size. The hit image is made on first
/// use: most renders do not ask for hit positions, and it is four times the colour image.
struct Raycaster::Targets {
    Targets(const GpuContext& context, int widthPx, int heightPx)
        : width(widthPx),
          height(heightPx),
          color(context, extent(), vk::Format::eR8G8B8A8Unorm,
                vk::ImageUsageFlagBits::eStorage | vk::ImageUsageFlagBits::eTransferSrc, "colour image"),
          colorReadback(context, pixelCount() * 4, vk::BufferUsageFlagBits::eTransferDst, GpuBuffer::Memory::HostVisible,
                        "colour readback") {}

    void makeHitTargets(const GpuContext& context) {
        if (hit) return;
        hit = std::make_unique<GpuImage>(context, extent(), vk::Format::eR32G32B32A32Sfloat,
                                         vk::ImageUsageFlagBits::eStorage | vk::ImageUsageFlagBits::eTransferSrc,
                                         "hit position image");
        hitReadback = std::make_unique<GpuBuffer>(context, pixelCount() * 16, vk::BufferUsageFlagBits::eTransferDst,
                                                  GpuBuffer::Memory::HostVisible, "hit position readback");
    }

    [[nodiscard]] vk::Extent3D extent() const {
        return {static_cast<uint32_t>(width), static_cast<uint32_t>(height), 1};
    }
    [[nodiscard]] vk::DeviceSize pixelCount() const {
        return static_cast<vk::DeviceSize>(width) * static_cast<vk::DeviceSize>(height);
    }

    int width;
    int height;
    GpuImage color;
    GpuBuffer colorReadback;
    std::unique_ptr<GpuImage> hit;
    std::unique_ptr<GpuBuffer> hitReadback;
};

/// What one image of a batch needs of its own: its uniforms, its timer and its output images
/// (by size). Slot i uses descriptor set i of every pipeline.
struct Raycaster::Slot {
    explicit Slot(const GpuContext& context)
        : uniforms(context, sizeof(shaders::RaycastUniforms), vk::BufferUsageFlagBits::eUniformBuffer,
                   GpuBuffer::Memory::HostVisible, "ray-casting uniforms"),
          fillUniforms(context, sizeof(shaders::RaycastUniforms), vk::BufferUsageFlagBits::eUniformBuffer,
                       GpuBuffer::Memory::HostVisible, "chord-table fill uniforms"),
          timer(context) {}

    Targets& targetsFor(const GpuContext& context, int width, int height) {
        auto& entry = targets[{width, height}];
        if (!entry) entry = std::make_unique<Targets>(context, width, height);
        return *entry;
    }

    GpuBuffer uniforms;
    GpuBuffer fillUniforms;  // the chord table's geometry, for a request that fills one
    std::unique_ptr<GpuBuffer> scratchChordTable;  // filled per frame once the tables' budget is spent
    std::unique_ptr<GpuBuffer> rayStarts;          // the tile pass's table: two floats per tile
    GpuTimer timer;
    std::map<std::pair<int, int>, std::unique_ptr<Targets>> targets;
    Targets* current = nullptr;  // the targets of the image this slot holds now
};

RenderBatch::RenderBatch(RenderBatch&& other) noexcept
    : mOwner(std::exchange(other.mOwner, nullptr)),
      mSlots(std::move(other.mSlots)),
      mIsWritingHits(std::move(other.mIsWritingHits)),
      mWork(std::move(other.mWork)) {
    other.mWork.reset();
}

RenderBatch::~RenderBatch() {
    mWork.reset();  // waits for the device before the slots can be reused
    if (mOwner) mOwner->releaseSlots(mSlots);
}

Raycaster::Raycaster(const GpuContext& context, const volumes::Volume& volume, const VolumeTexture& texture,
                     const volumes::BrickMinMax& bricks)
    : mContext(&context),
      mVolumeData(&volume),
      mVolume(&texture),
      mBricks(&bricks),
      mCubeMap(makeIdentityCubeMapTexture(context)),
      mSpeedBounds(makeIdentityCubeMapTexture(context)),  // unread until a warp's map comes
      mNoGradientVolume(makeEmptyGradientVolume(context)),
      mNoHitImage(context, vk::Extent3D(1, 1, 1), vk::Format::eR32G32B32A32Sfloat, vk::ImageUsageFlagBits::eStorage,
                  "unused hit position image"),
      mNoChordTable(context, CVC_POLYLINE_TABLE_BYTES_PER_TILE, vk::BufferUsageFlagBits::eStorageBuffer,
                    GpuBuffer::Memory::DeviceLocal, "unused chord table"),
      mNoRayStarts(context, 16, vk::BufferUsageFlagBits::eStorageBuffer, GpuBuffer::Memory::DeviceLocal,
                   "unused ray-start table") {
    if (volume.dims != texture.dims() || bricks.brickSize != volumes::kBrickSize ||
        bricks.brickDims != volumes::brickDimsFor(volume.dims)) {
        throw std::invalid_argument("volume, texture and brick min/max do not belong together");
    }
    submitAndWait(context, [&](const vk::raii::CommandBuffer& commands) {
        recordImageBarrier(commands, mNoHitImage, vk::ImageLayout::eUndefined, vk::ImageLayout::eGeneral);
    });
}

Raycaster::~Raycaster() = default;

void Raycaster::setChordTableBudget(std::uint64_t bytes) { mChordTableBudgetBytes = bytes; }

void Raycaster::setCubeMap(int size, std::span<const float> rgba) {
    mCubeMap = makeCubeMapTexture(*mContext, size, rgba);
    mHasCubeMap = true;
    mHasSpeedBounds = false;  // they belonged to the old map
    mChordTables.clear();  // their texels came from the old map
    mChordTableBytes = 0;
}

void Raycaster::setSpeedBounds(int size, std::span<const float> rgba) {
    mSpeedBounds = makeCubeMapTexture(*mContext, size, rgba);
    mHasSpeedBounds = true;
}

namespace {
// What a request's gradient volume holds: the B-spline's values at the voxels for BSplineAtVoxels
// (but not under the tricubic filter, whose normals are always the B-spline's own), the central
// differences for the rest.
GradientVolumeContent gradientVolumeContentOf(const RenderSettings& settings) {
    return settings.gradient == GradientFilter::BSplineAtVoxels && settings.filter != VolumeFilter::Tricubic
               ? GradientVolumeContent::BSplineAtVoxels
               : GradientVolumeContent::CentralDifferences;
}

// The shader's CVC_GRADIENT_*: one fetch of a gradient volume of the B-spline's values reads as
// central differences do; without that volume BSplineAtVoxels takes the B-spline's own normals.
int32_t shaderGradientOf(const RenderSettings& settings, bool hasGradientVolume) {
    switch (settings.gradient) {
        case GradientFilter::Central: return CVC_GRADIENT_CENTRAL;
        case GradientFilter::BSpline: return CVC_GRADIENT_BSPLINE;
        case GradientFilter::BSplineAtVoxels:
            return hasGradientVolume && gradientVolumeContentOf(settings) == GradientVolumeContent::BSplineAtVoxels
                       ? CVC_GRADIENT_CENTRAL
                       : CVC_GRADIENT_BSPLINE;
    }
    throw std::invalid_argument("unknown gradient filter");
}

// What the hit image receives (CVC_HIT_OUTPUT_*): the tests' ray parameters or normals in
// place of the positions, and nothing where no hit image is asked for.
int32_t hitOutputOf(const RenderSettings& settings) {
    if (!settings.isWritingHits) return CVC_HIT_OUTPUT_NONE;
    if (settings.isWritingRayStarts) return CVC_HIT_OUTPUT_RAY_STARTS;
    return settings.isWritingNormals ? CVC_HIT_OUTPUT_NORMAL : CVC_HIT_OUTPUT_POSITION;
}
}  // namespace

ComputePipeline& Raycaster::pipelineFor(const RenderSettings& settings, WarpMode warp, int chordTable, int rayStart) {
    const int32_t mode = settings.mode == RenderMode::Composite ? CVC_MODE_COMPOSITE : CVC_MODE_ISO;
    const int32_t filter = settings.filter == VolumeFilter::Tricubic ? CVC_FILTER_TRICUBIC : CVC_FILTER_TRILINEAR;
    const int32_t warpId = warpIdOf(warp);
    // Only iso mode refines hits: composite pipelines share one value.
    const int32_t refinement = mode == CVC_MODE_ISO ? settings.refinementSteps : 0;
    // Exact-warped rays skip only when asked to (RenderSettings::isSkippingBentRays).
    const bool isSkipping = settings.isSkipping && (warp != WarpMode::Exact || settings.isSkippingBentRays);
    // Features every ray of a dispatch takes alike are constants too: the compiler drops the
    // code of those a pipeline does not use, and no per-ray test of a uniform flag remains.
    const int32_t jitter = settings.isJittered ? 1 : 0;
    const int32_t hitOutput = hitOutputOf(settings);
    const int32_t gradientVolume = gradientVolumeFor(settings) ? 1 : 0;
    const int32_t gradient = shaderGradientOf(settings, gradientVolume != 0);
    const PipelineKey key{mode, filter, warpId, isSkipping ? 1 : 0, settings.isAdaptive ? 1 : 0,
                          settings.isCountingFetches ? 1 : 0, gradient, chordTable, rayStart, refinement,
                          jitter, hitOutput, gradientVolume};
    auto& slot = mPipelines[key];
    if (!slot) {
        // Order matches the constant_id numbers CVC_SPEC_MODE .. CVC_SPEC_GRADIENT_VOLUME.
        const int32_t constants[] = {mode, filter, warpId, std::get<3>(key), std::get<4>(key), std::get<5>(key), gradient,
                                     chordTable, rayStart, refinement, jitter, hitOutput, gradientVolume};
        slot = std::make_unique<ComputePipeline>(
            *mContext, raycast_spv, raycastDescriptorTypes(),
            0, "ray caster", constants, static_cast<uint32_t>(kMaxImagesInFlight));
    }
    return *slot;
}

ComputePipeline& Raycaster::rayStartFillPipelineFor(WarpMode warp, int chordTable) {
    // The pass builds each pixel's segment and reads the distance map; the other features do not
    // reach it, so one pipeline per warp and chord-table use serves every request.
    return pipelineFor(rayPassSettings(), warp, chordTable, CVC_RAY_START_FILL);
}

const TransferTable& Raycaster::transferTableFor(const std::string& name) {
    auto found = mTransferTables.find(name);
    if (found == mTransferTables.end()) found = mTransferTables.emplace(name, tabulate(transferFunctionPreset(name))).first;
    return found->second;
}

std::string Raycaster::transferNameOf(const RenderSettings& settings) {
    // Iso mode reads no table, but the binding needs one.
    return settings.mode == RenderMode::Composite ? settings.transferFunction : "colon-wall";
}

const SampledTexture& Raycaster::transferTextureFor(const RenderSettings& settings) {
    const std::string name = transferNameOf(settings);
    // A fixed step gets the table corrected for it (no power per sample); the adaptive step's
    // samples correct the reference opacities themselves.
    const bool isCorrected = settings.mode == RenderMode::Composite && !settings.isAdaptive;
    const double stepMm = baseStepMm(settings);
    std::ostringstream key;
    key.precision(17);
    key << name;
    if (isCorrected) key << '@' << stepMm;
    auto found = mTransferTextures.find(key.str());
    if (found == mTransferTextures.end()) {
        const TransferTable& table = transferTableFor(name);
        found = mTransferTextures
                    .emplace(key.str(), makeTransferTexture(*mContext, isCorrected ? correctedForStep(table, stepMm) : table))
                    .first;
    }
    return found->second;
}

double Raycaster::baseStepMm(const RenderSettings& settings) const {
    const glm::dvec3 spacing = mVolume->spacingMm();
    return settings.stepVoxels * std::min({spacing.x, spacing.y, spacing.z});
}

const SampledTexture& Raycaster::skipDistanceFor(const RenderSettings& settings) {
    std::ostringstream key;
    key.precision(17);
    key << settings.skipCellVoxels << ':';
    if (settings.mode == RenderMode::IsoSurface) {
        key << "iso:" << settings.isoHu;
    } else {
        key << "tf:" << settings.transferFunction;
    }
    auto found = mSkipDistances.find(key.str());
    if (found == mSkipDistances.end()) {
        const int cell = settings.skipCellVoxels;
        if (cell != volumes::kBrickSize && !mFinerCells.count(cell)) {
            mFinerCells.emplace(cell, volumes::buildBrickMinMax(*mVolumeData, cell));
        }
        const volumes::BrickMinMax& cells = cell == volumes::kBrickSize ? *mBricks : mFinerCells.at(cell);
        // A cell is occupied when any sample in it could stop the ray: for an iso-surface, when
        // its maximum reaches the iso value. Cells wholly inside tissue count too: a step longer
        // than the thin layer of cells that straddle the iso value can land in one, and the
        // unskipped ray would stop there.
        const double iso = settings.isoHu;
        const std::vector<uint8_t> occupied =
            settings.mode == RenderMode::IsoSurface
                ? volumes::bricksForPredicate(cells, [iso](int16_t, int16_t maxHu) { return maxHu >= iso; })
                : volumes::bricksForOpacity(cells, opacityTableOf(transferTableFor(settings.transferFunction)));
        found = mSkipDistances
                    .emplace(key.str(), makeSkipDistanceTexture(*mContext, cells.brickDims,
                                                                chebyshevDistanceMap(occupied, cells.brickDims)))
                    .first;
    }
    return found->second;
}

const SampledTexture* Raycaster::gradientVolumeFor(const RenderSettings& settings) {
    if (!settings.isUsingGradientVolume || mIsGradientVolumeTooLarge) return nullptr;
    const GradientVolumeContent content = gradientVolumeContentOf(settings);
    auto found = mGradientVolumes.find(content);
    if (found == mGradientVolumes.end()) {
        try {
            found = mGradientVolumes.emplace(content, makeGradientVolume(*mContext, *mVolumeData, content)).first;
        } catch (const DeviceMemoryError&) {
            // The taps give the same normals (but for rounding; the B-spline's own for
            // BSplineAtVoxels) at more fetches per shaded sample.
            mIsGradientVolumeTooLarge = true;
            return nullptr;
        }
    }
    return &found->second;
}

void Raycaster::validateRequest(const RenderRequest& request) const {
    validateRenderSettings(request.settings);
    const ViewRays& rays = request.rays;
    if (rays.width < 1 || rays.height < 1 || rays.width > kMaxImageSide || rays.height > kMaxImageSide) {
        throw std::invalid_argument("image size " + std::to_string(rays.width) + "x" + std::to_string(rays.height) +
                                    " is outside 1.." + std::to_string(kMaxImageSide));
    }
    (void)wallNormalOf(rays);  // throws for a degenerate image plane
    if (request.warp.mode == WarpMode::EyeCentred) {
        throw std::logic_error("an eye-centred warp is a chord about the eye: wallView makes it one");
    }
    if (request.warp.mode != WarpMode::None && !mHasCubeMap) {
        throw std::logic_error("a warped render needs setCubeMap first");
    }
    if (request.warp.mode == WarpMode::Exact && request.settings.isSkipping && request.settings.isSkippingBentRays &&
        !mHasSpeedBounds) {
        throw std::logic_error("skipping along bent rays needs setSpeedBounds for the cube map first");
    }
}

RenderedImage Raycaster::render(const ViewRays& rays, const RenderSettings& settings, const Warp& warp) {
    const RenderRequest request{rays, settings, warp};
    RenderBatch batch = submit(std::span(&request, 1));
    return std::move(collect(batch).front());
}

RenderBatch Raycaster::submit(std::span<const RenderRequest> asked) {
    for (const auto& request : asked) validateRequest(request);
    std::vector<RenderRequest> requests;
    requests.reserve(asked.size());
    for (const auto& request : asked) requests.push_back(effectiveRequest(request));
    const auto busy = static_cast<std::size_t>(std::count(mIsSlotBusy.begin(), mIsSlotBusy.end(), true));
    if (busy + requests.size() > static_cast<std::size_t>(kMaxImagesInFlight)) {
        throw std::logic_error("more than " + std::to_string(kMaxImagesInFlight) +
                               " images submitted and not collected");
    }
    RenderBatch batch;
    batch.mOwner = this;
    for (const auto& request : requests) {
        std::size_t index = 0;
        while (index < mIsSlotBusy.size() && mIsSlotBusy[index]) ++index;
        if (index == mSlots.size()) {
            mSlots.push_back(std::make_unique<Slot>(*mContext));
            mIsSlotBusy.push_back(false);
        }
        mIsSlotBusy[index] = true;
        batch.mSlots.push_back(static_cast<int>(index));
        batch.mIsWritingHits.push_back(request.settings.isWritingHits);
    }
    // Textures, maps, pipelines and chord tables are made before recording (each may submit
    // uploads itself).
    std::vector<ChordTableUse> chordTables;
    for (std::size_t i = 0; i < requests.size(); ++i) {
        const RenderSettings& settings = requests[i].settings;
        transferTextureFor(settings);
        skipDistanceFor(settings);
        chordTables.push_back(chordTableFor(requests[i], batch.mSlots[i]));
        const int chordTable = chordTables.back().table ? CVC_CHORD_TABLE_READ : CVC_CHORD_TABLE_NONE;
        const bool isStartPass = usesRayStartPass(requests[i], chordTables.back().table != nullptr);
        const WarpMode warp = requests[i].warp.mode;
        pipelineFor(settings, warp, chordTable, isStartPass ? CVC_RAY_START_READ : CVC_RAY_START_NONE);
        if (chordTables.back().isFilling) {
            pipelineFor(rayPassSettings(), warp, CVC_CHORD_TABLE_FILL, CVC_RAY_START_NONE);
            rayStartFillPipelineFor(warp, CVC_CHORD_TABLE_FILL);
        }
        if (isStartPass) rayStartFillPipelineFor(requests[i].warp.mode, chordTable);
    }
    batch.mWork.emplace(*mContext, [&](const vk::raii::CommandBuffer& commands) {
        for (std::size_t i = 0; i < requests.size(); ++i) {
            recordRequest(commands, requests[i], batch.mSlots[i], chordTables[i]);
        }
    });
    return batch;
}

std::vector<RenderedImage> Raycaster::collect(RenderBatch& batch) {
    if (batch.mOwner != this || !batch.mWork) throw std::logic_error("collect() of a batch this ray caster did not submit");
    batch.mWork->wait();
    std::vector<RenderedImage> images;
    images.reserve(batch.mSlots.size());
    for (std::size_t i = 0; i < batch.mSlots.size(); ++i) {
        Slot& slot = *mSlots[static_cast<std::size_t>(batch.mSlots[i])];
        Targets& targets = *slot.current;
        RenderedImage image;
        image.width = targets.width;
        image.height = targets.height;
        image.rgba.resize(static_cast<std::size_t>(targets.pixelCount()) * 4);
        targets.colorReadback.read(std::as_writable_bytes(std::span(image.rgba)));
        if (batch.mIsWritingHits[i]) {
            image.hitMm.resize(static_cast<std::size_t>(targets.pixelCount()) * 4);
            targets.hitReadback->read(std::as_writable_bytes(std::span(image.hitMm)));
        }
        image.deviceMs = slot.timer.elapsedMs();
        images.push_back(std::move(image));
    }
    batch.mWork.reset();
    releaseSlots(batch.mSlots);
    batch.mSlots.clear();
    batch.mOwner = nullptr;
    return images;
}

Raycaster::ChordTableUse Raycaster::chordTableFor(const RenderRequest& request, int slotIndex) {
    const Warp& warp = request.warp;
    const bool isTabled = warp.mode == WarpMode::Chord || warp.mode == WarpMode::Polyline;
    if (!isTabled || !request.settings.isUsingChordTable) return {};
    // With the map centre outside the volume the chord's reach changes with the pose, so no
    // two frames would share a table: such rays fetch per ray (the same for every run).
    const auto [boxMin, boxMax] = volumeBoxMm();
    if (glm::any(glm::lessThan(warp.mapCentreMm, boxMin)) || glm::any(glm::greaterThan(warp.mapCentreMm, boxMax))) {
        return {};
    }
    // The key: everything the texels depend on, in CAVE axes about the map centre, where a
    // display's walls and eyes stay put while the pose moves them through the volume.
    // Quantised to a nanometre, far below what moves a texel, far above double's rounding.
    const ViewRays& rays = request.rays;
    const glm::dmat3 toCave = glm::transpose(warp.caveToVolume);
    std::vector<long long> key{static_cast<long long>(warp.mode)};
    auto add = [&key](double value) { key.push_back(std::llround(value * 1e6)); };
    auto addVector = [&add](const glm::dvec3& v) {
        for (int axis = 0; axis < 3; ++axis) add(v[axis]);
    };
    addVector(toCave * (rays.eyeMm - warp.mapCentreMm));
    addVector(toCave * (rays.wallOriginMm - warp.mapCentreMm));
    addVector(toCave * rays.wallUMm);
    addVector(toCave * rays.wallVMm);
    add(rays.nearMm);
    add(chordReachMm(warp.mapCentreMm));
    key.push_back(rays.width);
    key.push_back(rays.height);
    // The table is filled from the key's own values, the display's geometry in CAVE axes about
    // a centre at the origin, not from this request's pose: then its texels do not depend on
    // which frame came first, and a resumed run or another rank writes the same images.
    ChordTableUse use;
    use.canonical.settings = request.settings;
    use.canonical.warp.mode = warp.mode;
    auto value = [&key](std::size_t index) { return static_cast<double>(key[index + 1]) * 1e-6; };
    auto vectorAt = [&value](std::size_t index) { return glm::dvec3(value(index), value(index + 1), value(index + 2)); };
    use.canonical.rays.eyeMm = vectorAt(0);
    use.canonical.rays.wallOriginMm = vectorAt(3);
    use.canonical.rays.wallUMm = vectorAt(6);
    use.canonical.rays.wallVMm = vectorAt(9);
    use.canonical.rays.nearMm = value(12);
    use.canonicalReachMm = value(13);
    use.canonical.rays.width = rays.width;
    use.canonical.rays.height = rays.height;
    auto found = mChordTables.find(key);
    if (found != mChordTables.end()) {
        use.table = found->second.get();
        return use;
    }
    // The table is laid out tile by tile (raycast.comp), whole tiles at the image's edges too.
    const vk::DeviceSize tiles = vk::DeviceSize{tilesAlong(rays.width)} * tilesAlong(rays.height);
    const vk::DeviceSize bytes = tiles * tableBytesPerTile(warp.mode);
    use.isFilling = true;
    if (mChordTableBytes + bytes > mChordTableBudgetBytes) {
        // Past the budget the table is filled for this frame alone, in the image's slot, so the
        // image is the same as a kept table's would be.
        auto& scratch = mSlots[static_cast<std::size_t>(slotIndex)]->scratchChordTable;
        if (!scratch || scratch->sizeBytes() < bytes) {
            scratch = std::make_unique<GpuBuffer>(*mContext, bytes, vk::BufferUsageFlagBits::eStorageBuffer,
                                                  GpuBuffer::Memory::DeviceLocal, "chord table of one frame");
        }
        use.table = scratch.get();
        return use;
    }
    auto table = std::make_unique<GpuBuffer>(*mContext, bytes, vk::BufferUsageFlagBits::eStorageBuffer,
                                             GpuBuffer::Memory::DeviceLocal, "chord table");
    mChordTableBytes += bytes;
    use.table = mChordTables.emplace(std::move(key), std::move(table)).first->second.get();
    return use;
}

std::pair<glm::dvec3, glm::dvec3> Raycaster::volumeBoxMm() const {
    // The box spans the voxels' outer faces, half a voxel beyond the centres.
    const auto dims = glm::dvec3(mVolume->dims()[0], mVolume->dims()[1], mVolume->dims()[2]);
    const glm::dvec3 spacing = mVolume->spacingMm();
    return {-0.5 * spacing, (dims - 0.5) * spacing};
}

double Raycaster::chordReachMm(const glm::dvec3& mapCentreMm) const {
    // The box's diagonal plus the centre's distance from it bounds the distance from the centre
    // to any point of the box, and it does not change as the pose moves a centre inside the box.
    const auto [boxMin, boxMax] = volumeBoxMm();
    const glm::dvec3 outside = glm::max(glm::max(boxMin - mapCentreMm, mapCentreMm - boxMax), glm::dvec3(0.0));
    return glm::length(boxMax - boxMin) + glm::length(outside);
}

void Raycaster::releaseSlots(const std::vector<int>& slots) {
    for (int index : slots) mIsSlotBusy[static_cast<std::size_t>(index)] = false;
}

shaders::RaycastUniforms Raycaster::uniformsFor(const RenderRequest& request, const TransferTable& table,
                                               double farReachMm) const {
    const ViewRays& rays = request.rays;
    const RenderSettings& settings = request.settings;
    const Warp& warp = request.warp;
    const glm::dvec3 wallNormal = wallNormalOf(rays);
    const auto dims = glm::dvec3(mVolume->dims()[0], mVolume->dims()[1], mVolume->dims()[2]);
    const glm::dvec3 spacing = mVolume->spacingMm();
    const double minSpacing = std::min({spacing.x, spacing.y, spacing.z});
    const auto [boxMin, boxMax] = volumeBoxMm();
    const double stepMm = baseStepMm(settings);
    const double minStepMm = settings.isAdaptive ? std::min(stepMm, settings.minStepVoxels * minSpacing) : stepMm;
    // Bound on a ray's steps: the longest segment any mode marches, over the shortest step.
    const double reachMm = 2.0 * glm::length(boxMax - boxMin) + 2.0 * glm::length(rays.eyeMm - 0.5 * (boxMin + boxMax)) +
                           2.0 * glm::length(rays.eyeMm - warp.mapCentreMm) + rays.nearMm;
    const double maxSteps = std::min(std::ceil(reachMm / minStepMm) + 16.0, 1.0e7);
    const double halfDistance = settings.lightHalfDistanceMm;
    const auto entries = static_cast<double>(table.rgba.size());

    const auto f = [](double value) { return static_cast<float>(value); };
    shaders::RaycastUniforms u{};
    u.eyeMm = glm::vec3(rays.eyeMm);
    u.nearMm = f(rays.nearMm);
    u.wallOriginMm = glm::vec3(rays.wallOriginMm);
    u.stepMm = f(stepMm);
    u.wallUMm = glm::vec3(rays.wallUMm);
    u.isoHu = f(settings.isoHu);
    u.wallVMm = glm::vec3(rays.wallVMm);
    u.speedBoundCosReach = f(std::cos(conformal::kSpeedBoundReachRadians));
    u.wallNormal = glm::vec3(wallNormal);
    u.maxSteps = f(maxSteps);
    u.mapCentreMm = glm::vec3(warp.mapCentreMm);
    u.minStepMm = f(minStepMm);
    u.caveToVolume0 = glm::vec3(warp.caveToVolume[0]);
    u.maxStepMm = f(settings.maxStepVoxels * minSpacing);
    u.caveToVolume1 = glm::vec3(warp.caveToVolume[1]);
    u.radiansPerPixel = f(pixelAngleOf(rays));
    u.caveToVolume2 = glm::vec3(warp.caveToVolume[2]);
    u.opacityToStop = f(settings.earlyTerminationOpacity);
    u.boxMinMm = glm::vec3(boxMin);
    u.transferFirstHu = f(table.firstHu);
    u.boxMaxMm = glm::vec3(boxMax);
    u.transferIndexPerHu = f((entries - 1.0) / (entries * (table.lastHu - table.firstHu)));
    u.texFromMmScale = glm::vec3(1.0 / (dims * spacing));
    u.transferReferenceStepMm = f(kTransferReferenceStepMm);
    u.texFromMmOffset = glm::vec3(0.5 / dims);
    u.transferHalfEntry = f(0.5 / entries);
    u.volumeDims = glm::vec3(dims);
    u.skipCellVoxels = f(settings.skipCellVoxels);
    u.invSpacingMm = glm::vec3(1.0 / spacing);
    u.lightFalloffPerMm2 = halfDistance > 0.0 ? f(1.0 / (halfDistance * halfDistance)) : 0.0f;
    u.roughness = f(settings.roughness);
    u.fresnelF0 = f(settings.fresnel);
    u.ambient = f(settings.ambient);
    u.chordReachMm = f(farReachMm);
    u.imageSize = glm::uvec2(static_cast<uint32_t>(rays.width), static_cast<uint32_t>(rays.height));
    const VisibleHuRange visible = visibleHuRangeOf(table);
    u.transferVisibleFromHu = f(visible.fromHu);
    u.transferVisibleToHu = f(visible.toHu);
    u.jitterSeed = settings.jitterSeed;
    u.isLookingInEveryTile = settings.isLookingInEveryTile ? 1u : 0u;
    return u;
}

double Raycaster::chordReachFor(const Warp& warp) const {
    if (warp.mode != WarpMode::Exact) return chordReachMm(warp.mapCentreMm);
    // Exact mode marches all the way to the far end, so it stops at the farthest corner.
    const auto [boxMin, boxMax] = volumeBoxMm();
    const glm::dvec3 farCorner = glm::max(glm::abs(boxMin - warp.mapCentreMm), glm::abs(boxMax - warp.mapCentreMm));
    return glm::length(farCorner);
}

void Raycaster::bindResources(ComputePipeline& pipeline, uint32_t set, const GpuBuffer& uniforms, const GpuImage& color,
                              const GpuImage& hit, const SampledTexture& skipDistance, const SampledTexture& transfer,
                              const SampledTexture& gradientVolume, const GpuBuffer& chordTable,
                              const GpuBuffer& rayStarts) const {
    pipeline.bindBuffer(CVC_BINDING_UNIFORMS, uniforms, set);
    pipeline.bindSampledImage(CVC_BINDING_VOLUME, mVolume->image(), mVolume->sampler(), set);
    pipeline.bindStorageImage(CVC_BINDING_COLOR_IMAGE, color, set);
    pipeline.bindStorageImage(CVC_BINDING_HIT_IMAGE, hit, set);
    pipeline.bindSampledImage(CVC_BINDING_SKIP_DISTANCE, skipDistance.image, skipDistance.sampler, set);
    pipeline.bindSampledImage(CVC_BINDING_TRANSFER_FUNCTION, transfer.image, transfer.sampler, set);
    pipeline.bindSampledImage(CVC_BINDING_CUBE_MAP, mCubeMap.image, mCubeMap.sampler, set);
    pipeline.bindSampledImage(CVC_BINDING_SPEED_BOUND, mSpeedBounds.image, mSpeedBounds.sampler, set);
    pipeline.bindSampledImage(CVC_BINDING_GRADIENT_VOLUME, gradientVolume.image, gradientVolume.sampler, set);
    pipeline.bindBuffer(CVC_BINDING_CHORD_TABLE, chordTable, set);
    pipeline.bindBuffer(CVC_BINDING_RAY_START, rayStarts, set);
}

void Raycaster::recordRequest(const vk::raii::CommandBuffer& commands, const RenderRequest& request, int slotIndex,
                              ChordTableUse chordTable) {
    const ViewRays& rays = request.rays;
    const RenderSettings& settings = request.settings;
    const Warp& warp = request.warp;
    const auto set = static_cast<uint32_t>(slotIndex);
    Slot& slot = *mSlots[static_cast<std::size_t>(slotIndex)];
    Targets& targets = slot.targetsFor(*mContext, rays.width, rays.height);
    slot.current = &targets;
    if (settings.isWritingHits) targets.makeHitTargets(*mContext);
    const GpuImage& hitImage = settings.isWritingHits ? *targets.hit : mNoHitImage;

    const SampledTexture& transfer = transferTextureFor(settings);
    const TransferTable& table = transferTableFor(transferNameOf(settings));
    const SampledTexture& skipDistance = skipDistanceFor(settings);
    const GpuBuffer& chordTexels = chordTable.table ? *chordTable.table : mNoChordTable;
    const int chordTableUse = chordTable.table ? CVC_CHORD_TABLE_READ : CVC_CHORD_TABLE_NONE;
    const bool isStartPass = usesRayStartPass(request, chordTable.table != nullptr);
    const vk::DeviceSize tileCount = vk::DeviceSize{tilesAlong(rays.width)} * tilesAlong(rays.height);
    // Per tile: where its rays start, and whether their march looks at the distance map.
    const vk::DeviceSize rayStartBytes = tileCount * 2 * sizeof(float);
    if (isStartPass && (!slot.rayStarts || slot.rayStarts->sizeBytes() < rayStartBytes)) {
        slot.rayStarts = std::make_unique<GpuBuffer>(*mContext, rayStartBytes,
                                                     vk::BufferUsageFlagBits::eStorageBuffer,
                                                     GpuBuffer::Memory::DeviceLocal, "ray-start table");
    }
    const GpuBuffer& rayStarts = isStartPass ? *slot.rayStarts : mNoRayStarts;
    ComputePipeline& pipeline =
        pipelineFor(settings, warp.mode, chordTableUse, isStartPass ? CVC_RAY_START_READ : CVC_RAY_START_NONE);
    const SampledTexture* gradientVolume = gradientVolumeFor(settings);
    bindResources(pipeline, set, slot.uniforms, targets.color, hitImage, skipDistance, transfer,
                  gradientVolume ? *gradientVolume : mNoGradientVolume, chordTexels, rayStarts);

    const shaders::RaycastUniforms u = uniformsFor(request, table, chordReachFor(warp));
    slot.uniforms.write(std::as_bytes(std::span(&u, 1)));
    if (chordTable.isFilling) {
        const shaders::RaycastUniforms canonical = uniformsFor(chordTable.canonical, table, chordTable.canonicalReachMm);
        slot.fillUniforms.write(std::as_bytes(std::span(&canonical, 1)));
    }

    recordImageBarrier(commands, targets.color, vk::ImageLayout::eUndefined, vk::ImageLayout::eGeneral);
    if (settings.isWritingHits) {
        recordImageBarrier(commands, *targets.hit, vk::ImageLayout::eUndefined, vk::ImageLayout::eGeneral);
    }
    const vk::Extent3D imageGroups(tilesAlong(rays.width), tilesAlong(rays.height), 1);
    const auto recordShaderWriteBarrier = [&commands] {
        const vk::MemoryBarrier written(vk::AccessFlagBits::eShaderWrite, vk::AccessFlagBits::eShaderRead);
        commands.pipelineBarrier(vk::PipelineStageFlagBits::eComputeShader, vk::PipelineStageFlagBits::eComputeShader,
                                 {}, written, {}, {});
    };
    // The tile passes (the chord table's cone bounds, the ray starts) run one invocation per
    // tile: their work groups cover CVC_TILE_SIZE^2 tiles each.
    const vk::Extent3D tileGroups(tilesAlong(static_cast<int>(imageGroups.width)),
                                  tilesAlong(static_cast<int>(imageGroups.height)), 1);
    slot.timer.recordStart(commands);  // a table's fill and the tile pass count in the frame
    if (chordTable.isFilling) {
        // The chords, then each tile's cone bound from them.
        ComputePipeline& fill = pipelineFor(rayPassSettings(), warp.mode, CVC_CHORD_TABLE_FILL, CVC_RAY_START_NONE);
        bindResources(fill, set, slot.fillUniforms, targets.color, hitImage, skipDistance, transfer, mNoGradientVolume,
                      chordTexels, mNoRayStarts);
        fill.recordDispatch(commands, imageGroups, {}, set);
        recordShaderWriteBarrier();
        ComputePipeline& bounds = rayStartFillPipelineFor(warp.mode, CVC_CHORD_TABLE_FILL);
        bindResources(bounds, set, slot.fillUniforms, targets.color, hitImage, skipDistance, transfer,
                      mNoGradientVolume, chordTexels, mNoRayStarts);
        bounds.recordDispatch(commands, tileGroups, {}, set);
    }
    // The table may have been filled just now or by an earlier batch still on the queue.
    if (chordTable.table) recordShaderWriteBarrier();
    if (isStartPass) {
        ComputePipeline& tilePass = rayStartFillPipelineFor(warp.mode, chordTableUse);
        bindResources(tilePass, set, slot.uniforms, targets.color, hitImage, skipDistance, transfer, mNoGradientVolume,
                      chordTexels, rayStarts);
        tilePass.recordDispatch(commands, tileGroups, {}, set);
        recordShaderWriteBarrier();
    }
    pipeline.recordDispatch(commands, imageGroups, {}, set);
    slot.timer.recordEnd(commands);
    recordImageBarrier(commands, targets.color, vk::ImageLayout::eGeneral, vk::ImageLayout::eTransferSrcOptimal);
    const vk::ImageSubresourceLayers layers(vk::ImageAspectFlagBits::eColor, 0, 0, 1);
    const vk::BufferImageCopy region(0, 0, 0, layers, vk::Offset3D(0, 0, 0), targets.extent());
    commands.copyImageToBuffer(*targets.color.image(), vk::ImageLayout::eTransferSrcOptimal,
                               *targets.colorReadback.buffer(), region);
    if (settings.isWritingHits) {
        recordImageBarrier(commands, *targets.hit, vk::ImageLayout::eGeneral, vk::ImageLayout::eTransferSrcOptimal);
        commands.copyImageToBuffer(*targets.hit->image(), vk::ImageLayout::eTransferSrcOptimal,
                                   *targets.hitReadback->buffer(), region);
    }
}

}  // namespace engine
