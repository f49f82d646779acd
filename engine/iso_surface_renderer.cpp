#include "engine/iso_surface_renderer.h"

#include <cmath>
#include <cstring>
#include <stdexcept>

#include "engine/command_submission.h"
#include "engine/gpu_image.h"
#include "host_device.h"
#include "raycast_iso_spv.h"

namespace engine {

static_assert(sizeof(shaders::RaycastUniforms) == 12 * 16, "RaycastUniforms must be twelve vec4s (std140)");

/// Output images and their readback buffers for one image size.
struct IsoSurfaceRenderer::Targets {
    Targets(const GpuContext& context, int widthPx, int heightPx)
        : width(widthPx),
          height(heightPx),
          color(context, vk::Extent3D(static_cast<uint32_t>(width), static_cast<uint32_t>(height), 1),
                vk::Format::eR8G8B8A8Unorm, vk::ImageUsageFlagBits::eStorage | vk::ImageUsageFlagBits::eTransferSrc,
                "colour image"),
          hit(context, vk::Extent3D(static_cast<uint32_t>(width), static_cast<uint32_t>(height), 1),
              vk::Format::eR32G32B32A32Sfloat, vk::ImageUsageFlagBits::eStorage | vk::ImageUsageFlagBits::eTransferSrc,
              "hit position image"),
          colorReadback(context, pixelCount() * 4, vk::BufferUsageFlagBits::eTransferDst, GpuBuffer::Memory::HostVisible,
                        "colour readback"),
          hitReadback(context, pixelCount() * 16, vk::BufferUsageFlagBits::eTransferDst, GpuBuffer::Memory::HostVisible,
                      "hit position readback") {}

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

IsoSurfaceRenderer::IsoSurfaceRenderer(const GpuContext& context, const VolumeTexture& volume)
    : mContext(&context),
      mVolume(&volume),
      mPipeline(context, raycast_iso_spv,
                {vk::DescriptorType::eUniformBuffer, vk::DescriptorType::eCombinedImageSampler,
                 vk::DescriptorType::eStorageImage, vk::DescriptorType::eStorageImage},
                0, "iso-surface ray caster"),
      mUniforms(context, sizeof(shaders::RaycastUniforms), vk::BufferUsageFlagBits::eUniformBuffer,
                GpuBuffer::Memory::HostVisible, "ray-casting uniforms") {
    mPipeline.bindBuffer(CVC_BINDING_UNIFORMS, mUniforms);
    mPipeline.bindSampledImage(CVC_BINDING_VOLUME, volume.image(), volume.sampler());
}

IsoSurfaceRenderer::~IsoSurfaceRenderer() = default;

RenderedImage IsoSurfaceRenderer::render(const PinholeCamera& camera, const IsoSurfaceSettings& settings) {
    const CameraBasis basis = cameraBasis(camera);
    if (!(settings.stepVoxels >= 0.01 && settings.stepVoxels <= 8.0)) {
        throw std::invalid_argument("step of " + std::to_string(settings.stepVoxels) + " voxels is outside 0.01..8");
    }
    if (settings.bisectionSteps < 0 || settings.bisectionSteps > 32) {
        throw std::invalid_argument("bisection steps " + std::to_string(settings.bisectionSteps) + " outside 0..32");
    }
    if (!std::isfinite(settings.isoHu)) throw std::invalid_argument("iso value must be a finite number");

    if (!mTargets || mTargets->width != camera.width || mTargets->height != camera.height) {
        mTargets.reset();
        mTargets = std::make_unique<Targets>(*mContext, camera.width, camera.height);
        mPipeline.bindStorageImage(CVC_BINDING_COLOR_IMAGE, mTargets->color);
        mPipeline.bindStorageImage(CVC_BINDING_HIT_IMAGE, mTargets->hit);
    }

    // Uniforms: the box spans the voxels' outer faces, half a voxel beyond the centres.
    const auto dims = glm::dvec3(mVolume->dims()[0], mVolume->dims()[1], mVolume->dims()[2]);
    const glm::dvec3 spacing = mVolume->spacingMm();
    const double minSpacing = std::min({spacing.x, spacing.y, spacing.z});
    const double stepMm = settings.stepVoxels * minSpacing;
    const double diagonalMm = glm::length(dims * spacing);
    const double maxSteps = std::ceil(diagonalMm / stepMm) + 2.0;

    shaders::RaycastUniforms u{};
    u.eyeMm = glm::vec4(glm::vec3(camera.positionMm), 0.0f);
    u.forward = glm::vec4(glm::vec3(basis.forward), 0.0f);
    u.rightScaled = glm::vec4(glm::vec3(basis.rightScaled), 0.0f);
    u.upScaled = glm::vec4(glm::vec3(basis.upScaled), 0.0f);
    u.boxMinMm = glm::vec4(glm::vec3(-0.5 * spacing), 0.0f);
    u.boxMaxMm = glm::vec4(glm::vec3((dims - 0.5) * spacing), 0.0f);
    u.texFromMmScale = glm::vec4(glm::vec3(1.0 / (dims * spacing)), 0.0f);
    u.texFromMmOffset = glm::vec4(glm::vec3(0.5 / dims), 0.0f);
    u.voxelStepTex = glm::vec4(glm::vec3(1.0 / dims), 0.0f);
    u.invSpacingMm = glm::vec4(glm::vec3(1.0 / spacing), 0.0f);
    u.march = glm::vec4(static_cast<float>(stepMm), static_cast<float>(settings.isoHu),
                        static_cast<float>(settings.bisectionSteps), static_cast<float>(maxSteps));
    u.imageSize = glm::uvec4(static_cast<uint32_t>(camera.width), static_cast<uint32_t>(camera.height), 0u, 0u);
    mUniforms.write(std::as_bytes(std::span(&u, 1)));

    GpuTimer timer(*mContext);
    Targets& targets = *mTargets;
    submitAndWait(*mContext, [&](const vk::raii::CommandBuffer& commands) {
        recordImageBarrier(commands, targets.color, vk::ImageLayout::eUndefined, vk::ImageLayout::eGeneral);
        recordImageBarrier(commands, targets.hit, vk::ImageLayout::eUndefined, vk::ImageLayout::eGeneral);
        timer.recordStart(commands);
        const auto groups = [](int n) { return static_cast<uint32_t>((n + CVC_TILE_SIZE - 1) / CVC_TILE_SIZE); };
        mPipeline.recordDispatch(commands, vk::Extent3D(groups(camera.width), groups(camera.height), 1));
        timer.recordEnd(commands);
        recordImageBarrier(commands, targets.color, vk::ImageLayout::eGeneral, vk::ImageLayout::eTransferSrcOptimal);
        recordImageBarrier(commands, targets.hit, vk::ImageLayout::eGeneral, vk::ImageLayout::eTransferSrcOptimal);
        const vk::ImageSubresourceLayers layers(vk::ImageAspectFlagBits::eColor, 0, 0, 1);
        const vk::BufferImageCopy region(0, 0, 0, layers, vk::Offset3D(0, 0, 0), targets.color.extent());
        commands.copyImageToBuffer(*targets.color.image(), vk::ImageLayout::eTransferSrcOptimal,
                                   *targets.colorReadback.buffer(), region);
        commands.copyImageToBuffer(*targets.hit.image(), vk::ImageLayout::eTransferSrcOptimal,
                                   *targets.hitReadback.buffer(), region);
    });

    RenderedImage image;
    image.width = camera.width;
    image.height = camera.height;
    image.rgba.resize(static_cast<std::size_t>(targets.pixelCount()) * 4);
    image.hitMm.resize(static_cast<std::size_t>(targets.pixelCount()) * 4);
    targets.colorReadback.read(std::as_writable_bytes(std::span(image.rgba)));
    targets.hitReadback.read(std::as_writable_bytes(std::span(image.hitMm)));
    image.deviceMs = timer.elapsedMs();
    return image;
}

}  // namespace engine
