/// @brief A Vulkan 2D or 3D image with its memory and a view, in optimal tiling.
#pragma once

#include <string>

#include "engine/gpu_context.h"

namespace engine {

class GpuImage {
public:
    /// Creates a device-local image of `extent` (depth 1 for 2D) and a view of all of it.
    GpuImage(const GpuContext& context, vk::Extent3D extent, vk::Format format, vk::ImageUsageFlags usage,
             const std::string& debugName);

    [[nodiscard]] const vk::raii::Image& image() const { return mImage; }
    [[nodiscard]] const vk::raii::ImageView& view() const { return mView; }
    [[nodiscard]] vk::Extent3D extent() const { return mExtent; }
    [[nodiscard]] vk::Format format() const { return mFormat; }

private:
    vk::Extent3D mExtent;
    vk::Format mFormat;
    vk::raii::Image mImage;
    vk::raii::DeviceMemory mMemory{nullptr};
    vk::raii::ImageView mView{nullptr};
};

/// Records a layout transition of the whole colour image with a full memory dependency
/// between all earlier and later transfer and compute work (simple and always correct).
void recordImageBarrier(const vk::raii::CommandBuffer& commands, const GpuImage& image, vk::ImageLayout from,
                        vk::ImageLayout to);

}  // namespace engine
