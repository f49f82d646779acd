/// @brief A Vulkan 2D, 3D or cube image with its memory and a view, in optimal tiling, and the
/// upload of a whole image from host memory.
#pragma once

#include <span>
#include <string>

#include "engine/core/gpu_context.h"

namespace engine {

class GpuImage {
public:
    /// Creates a device-local image of `extent` (depth 1 for 2D) and a view of all of it.
    /// `isCube` makes a cube map: six square 2D layers in Vulkan face order, viewed as a cube.
    /// `isVolume` makes a 3D image and view whatever the depth: a volume of one slice is still
    /// read through a sampler3D, and binding a 2D view there is invalid.
    GpuImage(const GpuContext& context, vk::Extent3D extent, vk::Format format, vk::ImageUsageFlags usage,
             const std::string& debugName, bool isCube = false, bool isVolume = false);

    [[nodiscard]] const vk::raii::Image& image() const { return mImage; }
    [[nodiscard]] const vk::raii::ImageView& view() const { return mView; }
    [[nodiscard]] vk::Extent3D extent() const { return mExtent; }
    [[nodiscard]] vk::Format format() const { return mFormat; }
    [[nodiscard]] uint32_t layerCount() const { return mLayerCount; }

private:
    vk::Extent3D mExtent;
    vk::Format mFormat;
    uint32_t mLayerCount;
    vk::raii::Image mImage;
    vk::raii::DeviceMemory mMemory{nullptr};
    vk::raii::ImageView mView{nullptr};
};

/// Copies `texels` (tightly packed, layer after layer) into the whole image through a staging
/// buffer and leaves it in SHADER_READ_ONLY_OPTIMAL for sampling. The image needs TRANSFER_DST.
void uploadImage(const GpuContext& context, const GpuImage& image, std::span<const std::byte> texels);

/// Records a layout transition of the whole colour image with a full memory dependency
/// between all earlier and later transfer and compute work (simple and always correct).
void recordImageBarrier(const vk::raii::CommandBuffer& commands, const GpuImage& image, vk::ImageLayout from,
                        vk::ImageLayout to);

}  // namespace engine
