#include "engine/raycaster.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "engine/command_submission.h"
#include "engine/empty_space_map.h"
#include "host_device.h"
#include "raycast_spv.h"

namespace engine {

static_assert(sizeof(shaders::RaycastUniforms) == 20 * 16, "RaycastUniforms must be 20 vec4s (std140)");
static_assert(offsetof(shaders::RaycastUniforms, march) == 15 * 16, "march must follow the volume block");
static_assert(offsetof(shaders::RaycastUniforms, frame) == 19 * 16, "frame must be the last vec4");

namespace {

glm::vec4 vec4Of(const glm::dvec3& v, double w = 0.0) { return {glm::vec3(v), static_cast<float>(w)}; }

void validate(const RenderSettings& s) {
    auto require = [](bool condition, const std::string& what) {
        if (!condition) throw std::invalid_argument("render settings: " + what);
    };
    require(s.stepVoxels >= 0.01 && s.stepVoxels <= 8.0, "step must be 0.01..8 voxels");
    require(s.skipCellVoxels >= 1 && s.skipCellVoxels <= 64, "skipping cells must be 1..64 voxels");
    require(s.refinementSteps >= 0 && s.refinementSteps <= 32, "refinement steps must be 0..32");
    require(std::isfinite(s.isoHu), "iso value must be finite");
    require(s.minStepVoxels > 0.0 && s.minStepVoxels <= s.maxStepVoxels && s.maxStepVoxels <= 64.0,
            "adaptive step bounds must satisfy 0 < min <= max <= 64 voxels");
    require(s.earlyTerminationOpacity > 0.0 && s.earlyTerminationOpacity <= 1.0, "early termination opacity must be in (0, 1]");
    require(s.lightHalfDistanceMm >= 0.0 && std::isfinite(s.lightHalfDistanceMm), "light half distance must be >= 0");
    require(s.roughness > 0.0 && s.roughness <= 1.0 && s.fresnel >= 0.0 && s.fresnel <= 1.0 && s.ambient >= 0.0 &&
                s.ambient <= 1.0,
            "roughness in (0, 1], Fresnel and ambient in [0, 1]");
}

}  // namespace

/// Output images and their readback buffers for one image size.
struct Raycaster::Targets {
    Targets(const GpuContext& context, int widthPx, int heightPx)
        : width(widthPx),
          height(heightPx),
          color(context, extent(), vk::Format::eR8G8B8A8Unorm,
                vk::ImageUsageFlagBits::eStorage | vk::ImageUsageFlagBits::eTransferSrc, "colour image"),
          hit(context, extent(), vk::Format::eR32G32B32A32Sfloat,
              vk::ImageUsageFlagBits::eStorage | vk::ImageUsageFlagBits::eTransferSrc, "hit position image"),
          colorReadback(context, pixelCount() * 4, vk::BufferUsageFlagBits::eTransferDst, GpuBuffer::Memory::HostVisible,
                        "colour readback"),
          hitReadback(context, pixelCount() * 16, vk::BufferUsageFlagBits::eTransferDst, GpuBuffer::Memory::HostVisible,
                      "hit position readback") {}

    [[nodiscard]] vk::Extent3D extent() const {
        return {static_cast<uint32_t>(width), static_cast<uint32_t>(height), 1};
    }
    [[nodiscard]] vk::DeviceSize pixelCount() const {
        return static_cast<vk::DeviceSize>(width) * static_cast<vk::DeviceSize>(height);
    }

    int width;
    int height;
    GpuImage color;
    GpuImage hit;
    GpuBuffer colorReadback;
    GpuBuffer hitReadback;
};

Raycaster::Raycaster(const GpuContext& context, const volumes::Volume& volume, const VolumeTexture& texture,
                     const volumes::BrickMinMax& bricks)
    : mContext(&context),
      mVolumeData(&volume),
      mVolume(&texture),
      mBricks(&bricks),
      mUniforms(context, sizeof(shaders::RaycastUniforms), vk::BufferUsageFlagBits::eUniformBuffer,
                GpuBuffer::Memory::HostVisible, "ray-casting uniforms"),
      mCubeMap(makeIdentityCubeMapTexture(context)) {
    if (volume.dims != texture.dims() || bricks.brickSize != volumes::kBrickSize ||
        bricks.brickDims != volumes::brickDimsFor(volume.dims)) {
        throw std::invalid_argument("volume, texture and brick min/max do not belong together");
    }
}

Raycaster::~Raycaster() = default;

void Raycaster::setCubeMap(int size, std::span<const float> rgba) {
    mCubeMap = makeCubeMapTexture(*mContext, size, rgba);
    mHasCubeMap = true;
}

ComputePipeline& Raycaster::pipelineFor(const RenderSettings& settings, WarpMode warp) {
    const int32_t mode = settings.mode == RenderMode::Composite ? CVC_MODE_COMPOSITE : CVC_MODE_ISO;
    const int32_t filter = settings.filter == VolumeFilter::Tricubic ? CVC_FILTER_TRICUBIC : CVC_FILTER_TRILINEAR;
    const int32_t warpId = warp == WarpMode::Exact ? CVC_WARP_EXACT : warp == WarpMode::Chord ? CVC_WARP_CHORD : CVC_WARP_NONE;
    const PipelineKey key{mode, filter, warpId, settings.isSkipping ? 1 : 0, settings.isAdaptive ? 1 : 0,
                          settings.isCountingFetches ? 1 : 0};
    auto& slot = mPipelines[key];
    if (!slot) {
        // Order matches the constant_id numbers CVC_SPEC_MODE .. CVC_SPEC_COUNT_FETCHES.
        const int32_t constants[] = {mode, filter, warpId, std::get<3>(key), std::get<4>(key), std::get<5>(key)};
        slot = std::make_unique<ComputePipeline>(
            *mContext, raycast_spv,
            std::vector<vk::DescriptorType>{vk::DescriptorType::eUniformBuffer, vk::DescriptorType::eCombinedImageSampler,
                                            vk::DescriptorType::eStorageImage, vk::DescriptorType::eStorageImage,
                                            vk::DescriptorType::eCombinedImageSampler,
                                            vk::DescriptorType::eCombinedImageSampler,
                                            vk::DescriptorType::eCombinedImageSampler},
            0, "ray caster", constants);
    }
    return *slot;
}

const SampledTexture& Raycaster::transferTextureFor(const std::string& name) {
    auto found = mTransferTextures.find(name);
    if (found == mTransferTextures.end()) {
        const TransferTable table = tabulate(transferFunctionPreset(name));
        found = mTransferTextures.emplace(name, makeTransferTexture(*mContext, table)).first;
        mTransferTables.emplace(name, table);
    }
    return found->second;
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
                : volumes::bricksForOpacity(cells, opacityTableOf(mTransferTables.at(settings.transferFunction)));
        found = mSkipDistances
                    .emplace(key.str(), makeSkipDistanceTexture(*mContext, cells.brickDims,
                                                                chebyshevDistanceMap(occupied, cells.brickDims)))
                    .first;
    }
    return found->second;
}

RenderedImage Raycaster::render(const ViewRays& rays, const RenderSettings& settings, const Warp& warp) {
    validate(settings);
    if (rays.width < 1 || rays.height < 1 || rays.width > kMaxImageSide || rays.height > kMaxImageSide) {
        throw std::invalid_argument("image size " + std::to_string(rays.width) + "x" + std::to_string(rays.height) +
                                    " is outside 1.." + std::to_string(kMaxImageSide));
    }
    const glm::dvec3 wallNormal = wallNormalOf(rays);
    if (warp.mode != WarpMode::None && !mHasCubeMap) throw std::logic_error("a warped render needs setCubeMap first");

    const SampledTexture& transfer = transferTextureFor(settings.mode == RenderMode::Composite ? settings.transferFunction
                                                                                               : "colon-wall");
    const TransferTable& table = mTransferTables.at(settings.mode == RenderMode::Composite ? settings.transferFunction
                                                                                           : "colon-wall");
    const SampledTexture& skipDistance = skipDistanceFor(settings);
    ComputePipeline& pipeline = pipelineFor(settings, warp.mode);

    auto& slot = mTargets[{rays.width, rays.height}];
    if (!slot) slot = std::make_unique<Targets>(*mContext, rays.width, rays.height);
    Targets& targets = *slot;
    pipeline.bindBuffer(CVC_BINDING_UNIFORMS, mUniforms);
    pipeline.bindSampledImage(CVC_BINDING_VOLUME, mVolume->image(), mVolume->sampler());
    pipeline.bindStorageImage(CVC_BINDING_COLOR_IMAGE, targets.color);
    pipeline.bindStorageImage(CVC_BINDING_HIT_IMAGE, targets.hit);
    pipeline.bindSampledImage(CVC_BINDING_SKIP_DISTANCE, skipDistance.image, skipDistance.sampler);
    pipeline.bindSampledImage(CVC_BINDING_TRANSFER_FUNCTION, transfer.image, transfer.sampler);
    pipeline.bindSampledImage(CVC_BINDING_CUBE_MAP, mCubeMap.image, mCubeMap.sampler);

    // Geometry of the volume: the box spans the voxels' outer faces, half a voxel beyond the centres.
    const auto dims = glm::dvec3(mVolume->dims()[0], mVolume->dims()[1], mVolume->dims()[2]);
    const glm::dvec3 spacing = mVolume->spacingMm();
    const double minSpacing = std::min({spacing.x, spacing.y, spacing.z});
    const glm::dvec3 boxMin = -0.5 * spacing;
    const glm::dvec3 boxMax = (dims - 0.5) * spacing;
    const double stepMm = settings.stepVoxels * minSpacing;
    const double minStepMm = settings.isAdaptive ? std::min(stepMm, settings.minStepVoxels * minSpacing) : stepMm;
    // Bound on a ray's steps: the longest segment any mode marches, over the shortest step.
    const double reachMm = 2.0 * glm::length(boxMax - boxMin) + 2.0 * glm::length(rays.eyeMm - 0.5 * (boxMin + boxMax)) +
                           2.0 * glm::length(rays.eyeMm - warp.mapCentreMm) + rays.nearMm;
    const double maxSteps = std::min(std::ceil(reachMm / minStepMm) + 16.0, 1.0e7);
    const double halfDistance = settings.lightHalfDistanceMm;
    const auto entries = static_cast<double>(table.rgba.size());

    shaders::RaycastUniforms u{};
    u.eyeMm = vec4Of(rays.eyeMm, rays.nearMm);
    u.wallOriginMm = vec4Of(rays.wallOriginMm);
    u.wallUMm = vec4Of(rays.wallUMm);
    u.wallVMm = vec4Of(rays.wallVMm);
    u.wallNormal = vec4Of(wallNormal);
    u.mapCentreMm = vec4Of(warp.mapCentreMm);
    u.caveToVolume0 = vec4Of(warp.caveToVolume[0]);
    u.caveToVolume1 = vec4Of(warp.caveToVolume[1]);
    u.caveToVolume2 = vec4Of(warp.caveToVolume[2]);
    u.boxMinMm = vec4Of(boxMin);
    u.boxMaxMm = vec4Of(boxMax);
    u.texFromMmScale = vec4Of(1.0 / (dims * spacing));
    u.texFromMmOffset = vec4Of(0.5 / dims);
    u.volumeDims = vec4Of(dims, settings.skipCellVoxels);
    u.invSpacingMm = vec4Of(1.0 / spacing);
    u.march = glm::vec4(static_cast<float>(stepMm), static_cast<float>(settings.isoHu),
                        static_cast<float>(settings.refinementSteps), static_cast<float>(maxSteps));
    u.adaptive = glm::vec4(static_cast<float>(minStepMm), static_cast<float>(settings.maxStepVoxels * minSpacing),
                           static_cast<float>(pixelAngleOf(rays)), static_cast<float>(settings.earlyTerminationOpacity));
    u.transfer = glm::vec4(static_cast<float>(table.firstHu),
                           static_cast<float>((entries - 1.0) / (entries * (table.lastHu - table.firstHu))),
                           1.0f, static_cast<float>(0.5 / entries));
    u.shading = glm::vec4(halfDistance > 0.0 ? static_cast<float>(1.0 / (halfDistance * halfDistance)) : 0.0f,
                          static_cast<float>(settings.roughness), static_cast<float>(settings.fresnel),
                          static_cast<float>(settings.ambient));
    u.frame = glm::uvec4(static_cast<uint32_t>(rays.width), static_cast<uint32_t>(rays.height), settings.jitterSeed,
                         (settings.isWritingHits ? CVC_FLAG_WRITE_HITS : 0u) | (settings.isJittered ? CVC_FLAG_JITTER : 0u));
    mUniforms.write(std::as_bytes(std::span(&u, 1)));

    GpuTimer timer(*mContext);
    submitAndWait(*mContext, [&](const vk::raii::CommandBuffer& commands) {
        recordImageBarrier(commands, targets.color, vk::ImageLayout::eUndefined, vk::ImageLayout::eGeneral);
        recordImageBarrier(commands, targets.hit, vk::ImageLayout::eUndefined, vk::ImageLayout::eGeneral);
        timer.recordStart(commands);
        const auto groups = [](int n) { return static_cast<uint32_t>((n + CVC_TILE_SIZE - 1) / CVC_TILE_SIZE); };
        pipeline.recordDispatch(commands, vk::Extent3D(groups(rays.width), groups(rays.height), 1));
        timer.recordEnd(commands);
        recordImageBarrier(commands, targets.color, vk::ImageLayout::eGeneral, vk::ImageLayout::eTransferSrcOptimal);
        const vk::ImageSubresourceLayers layers(vk::ImageAspectFlagBits::eColor, 0, 0, 1);
        const vk::BufferImageCopy region(0, 0, 0, layers, vk::Offset3D(0, 0, 0), targets.extent());
        commands.copyImageToBuffer(*targets.color.image(), vk::ImageLayout::eTransferSrcOptimal,
                                   *targets.colorReadback.buffer(), region);
        if (settings.isWritingHits) {
            recordImageBarrier(commands, targets.hit, vk::ImageLayout::eGeneral, vk::ImageLayout::eTransferSrcOptimal);
            commands.copyImageToBuffer(*targets.hit.image(), vk::ImageLayout::eTransferSrcOptimal,
                                       *targets.hitReadback.buffer(), region);
        }
    });

    RenderedImage image;
    image.width = rays.width;
    image.height = rays.height;
    image.rgba.resize(static_cast<std::size_t>(targets.pixelCount()) * 4);
    targets.colorReadback.read(std::as_writable_bytes(std::span(image.rgba)));
    if (settings.isWritingHits) {
        image.hitMm.resize(static_cast<std::size_t>(targets.pixelCount()) * 4);
        targets.hitReadback.read(std::as_writable_bytes(std::span(image.hitMm)));
    }
    image.deviceMs = timer.elapsedMs();
    return image;
}

}  // namespace engine
