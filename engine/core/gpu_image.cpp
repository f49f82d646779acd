#include "engine/core/gpu_image.h"

#include <stdexcept>

#include "engine/core/command_submission.h"
#include "engine/core/gpu_buffer.h"

namespace engine {
namespace {

vk::ImageCreateInfo imageInfo(vk::Extent3D extent, vk::Format format, vk::ImageUsageFlags usage, bool isCube,
                              bool isVolume) {
    return vk::ImageCreateInfo(isCube ? vk::ImageCreateFlagBits::eCubeCompatible : vk::ImageCreateFlags{},
                               isVolume || extent.depth > 1 ? vk::ImageType::e3D : vk::ImageType::e2D, format, extent, 1,
                               isCube ? 6 : 1, vk::SampleCountFlagBits::e1, vk::ImageTiling::eOptimal, usage,
                               vk::SharingMode::eExclusive, {}, vk::ImageLayout::eUndefined);
}

vk::ImageViewType viewTypeOf(vk::Extent3D extent, bool isCube, bool isVolume) {
    if (isCube) return vk::ImageViewType::eCube;
    return isVolume || extent.depth > 1 ? vk::ImageViewType::e3D : vk::ImageViewType::e2D;
}

}  // namespace

GpuImage::GpuImage(const GpuContext& context, vk::Extent3D extent, vk::Format format, vk::ImageUsageFlags usage,
                   const std::string& debugName, bool isCube, bool isVolume)
    : mExtent(extent),
      mFormat(format),
      mLayerCount(isCube ? 6 : 1),
      mImage(context.device(), imageInfo(extent, format, usage, isCube, isVolume)) {
    const auto requirements = mImage.getMemoryRequirements();
    mMemory = context.allocateMemory(requirements, vk::MemoryPropertyFlagBits::eDeviceLocal, debugName);
    mImage.bindMemory(*mMemory, 0);
    mView = vk::raii::ImageView(
        context.device(),
        vk::ImageViewCreateInfo({}, *mImage, viewTypeOf(extent, isCube, isVolume), format, {},
                                vk::ImageSubresourceRange(vk::ImageAspectFlagBits::eColor, 0, 1, 0, mLayerCount)));
    context.setDebugName(mImage, debugName);
}

void uploadImage(const GpuContext& context, const GpuImage& image, std::span<const std::byte> texels) {
    GpuBuffer staging(context, texels.size(), vk::BufferUsageFlagBits::eTransferSrc, GpuBuffer::Memory::HostVisible,
                      "image upload staging");
    staging.write(texels);
    submitAndWait(context, [&](const vk::raii::CommandBuffer& commands) {
        recordImageBarrier(commands, image, vk::ImageLayout::eUndefined, vk::ImageLayout::eTransferDstOptimal);
        vk::BufferImageCopy region(0, 0, 0,
                                   vk::ImageSubresourceLayers(vk::ImageAspectFlagBits::eColor, 0, 0, image.layerCount()),
                                   vk::Offset3D(0, 0, 0), image.extent());
        commands.copyBufferToImage(*staging.buffer(), *image.image(), vk::ImageLayout::eTransferDstOptimal, region);
        recordImageBarrier(commands, image, vk::ImageLayout::eTransferDstOptimal, vk::ImageLayout::eShaderReadOnlyOptimal);
    });
}

void recordImageBarrier(const vk::raii::CommandBuffer& commands, const GpuImage& image, vk::ImageLayout from,
                        vk::ImageLayout to) {
    const auto access = vk::AccessFlagBits::eShaderRead | vk::AccessFlagBits::eShaderWrite |
                        vk::AccessFlagBits::eTransferRead | vk::AccessFlagBits::eTransferWrite;
    vk::ImageMemoryBarrier barrier(access, access, from, to, VK_QUEUE_FAMILY_IGNORED, VK_QUEUE_FAMILY_IGNORED,
                                   *image.image(),
                                   vk::ImageSubresourceRange(vk::ImageAspectFlagBits::eColor, 0, 1, 0, image.layerCount()));
    const auto stages = vk::PipelineStageFlagBits::eComputeShader | vk::PipelineStageFlagBits::eTransfer;
    commands.pipelineBarrier(stages, stages, {}, {}, {}, barrier);
}

}  // namespace engine
