#include "engine/gpu_image.h"

namespace engine {
namespace {

vk::ImageCreateInfo imageInfo(vk::Extent3D extent, vk::Format format, vk::ImageUsageFlags usage) {
    return vk::ImageCreateInfo({}, extent.depth > 1 ? vk::ImageType::e3D : vk::ImageType::e2D, format, extent, 1, 1,
                               vk::SampleCountFlagBits::e1, vk::ImageTiling::eOptimal, usage,
                               vk::SharingMode::eExclusive, {}, vk::ImageLayout::eUndefined);
}

}  // namespace

GpuImage::GpuImage(const GpuContext& context, vk::Extent3D extent, vk::Format format, vk::ImageUsageFlags usage,
                   const std::string& debugName)
    : mExtent(extent), mFormat(format), mImage(context.device(), imageInfo(extent, format, usage)) {
    const auto requirements = mImage.getMemoryRequirements();
    mMemory = vk::raii::DeviceMemory(
        context.device(),
        vk::MemoryAllocateInfo(requirements.size, context.findMemoryType(requirements.memoryTypeBits,
                                                                         vk::MemoryPropertyFlagBits::eDeviceLocal)));
    mImage.bindMemory(*mMemory, 0);
    mView = vk::raii::ImageView(
        context.device(),
        vk::ImageViewCreateInfo({}, *mImage, extent.depth > 1 ? vk::ImageViewType::e3D : vk::ImageViewType::e2D,
                                format, {}, vk::ImageSubresourceRange(vk::ImageAspectFlagBits::eColor, 0, 1, 0, 1)));
    context.setDebugName(mImage, debugName);
}

void recordImageBarrier(const vk::raii::CommandBuffer& commands, const GpuImage& image, vk::ImageLayout from,
                        vk::ImageLayout to) {
    const auto access = vk::AccessFlagBits::eShaderRead | vk::AccessFlagBits::eShaderWrite |
                        vk::AccessFlagBits::eTransferRead | vk::AccessFlagBits::eTransferWrite;
    vk::ImageMemoryBarrier barrier(access, access, from, to, VK_QUEUE_FAMILY_IGNORED, VK_QUEUE_FAMILY_IGNORED,
                                   *image.image(),
                                   vk::ImageSubresourceRange(vk::ImageAspectFlagBits::eColor, 0, 1, 0, 1));
    const auto stages = vk::PipelineStageFlagBits::eComputeShader | vk::PipelineStageFlagBits::eTransfer;
    commands.pipelineBarrier(stages, stages, {}, {}, {}, barrier);
}

}  // namespace engine
