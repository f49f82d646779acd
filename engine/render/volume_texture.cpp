#include "engine/render/volume_texture.h"

#include <algorithm>
#include <memory>

#include "engine/core/command_submission.h"
#include "engine/core/gpu_buffer.h"
#include "engine/render/sampled_textures.h"

namespace engine {
namespace {

constexpr vk::DeviceSize kSlabBytes = 32u << 20;

/// The image's extent; a volume larger than the device's image limit or than one allocation of
/// its memory is refused here, before anything is allocated, with what would fit.
vk::Extent3D extentOf(const volumes::Volume& volume, const GpuContext& context) {
    const uint32_t limit = context.physicalDevice().getProperties().limits.maxImageDimension3D;
    for (int axis = 0; axis < 3; ++axis) {
        if (static_cast<uint32_t>(volume.dims[static_cast<std::size_t>(axis)]) > limit) {
            throw std::runtime_error("volume of " + std::to_string(volume.dims[static_cast<std::size_t>(axis)]) +
                                     " voxels along axis " + std::to_string(axis) + " exceeds the device's 3D image limit of " +
                                     std::to_string(limit));
        }
    }
    const vk::DeviceSize largest = context.largestAllocationBytes(vk::MemoryPropertyFlagBits::eDeviceLocal);
    const vk::DeviceSize bytes = VolumeTexture::bytesFor(volume.dims);
    if (bytes > largest) {
        throw DeviceMemoryError("a volume of " + std::to_string(volume.dims[0]) + "x" + std::to_string(volume.dims[1]) +
                                    "x" + std::to_string(volume.dims[2]) + " voxels needs " +
                                    mebibytesText(bytes) + " on the device, and " + context.deviceName() + " allows " +
                                    mebibytesText(largest) + " in one image: at most " +
                                    std::to_string(VolumeTexture::slicesThatFit(volume.dims, largest)) +
                                    " of its slices fit (crop it, or choose a larger --device)",
                                largest);
    }
    return vk::Extent3D(static_cast<uint32_t>(volume.dims[0]), static_cast<uint32_t>(volume.dims[1]),
                        static_cast<uint32_t>(volume.dims[2]));
}

/// Runs `perSlab(firstZ, depth, sliceBytes)` over z-slabs of texels of `texelBytes` that each fit
/// kSlabBytes.
template <typename Function>
void forEachSlab(const std::array<int, 3>& dims, vk::DeviceSize texelBytes, Function perSlab) {
    const vk::DeviceSize sliceBytes =
        static_cast<vk::DeviceSize>(dims[0]) * static_cast<vk::DeviceSize>(dims[1]) * texelBytes;
    const int slicesPerSlab = static_cast<int>(std::max<vk::DeviceSize>(1, kSlabBytes / sliceBytes));
    for (int z = 0; z < dims[2]; z += slicesPerSlab) perSlab(z, std::min(slicesPerSlab, dims[2] - z), sliceBytes);
}

}  // namespace

void uploadInSlabs(const GpuContext& context, const GpuImage& image, const std::array<int, 3>& dims,
                   vk::DeviceSize texelBytes, const std::function<void(int, int, std::byte*)>& fillSlab) {
    bool isFirst = true;
    // One staging buffer serves every slab: on a CPU device the pages of each new buffer would be
    // faulted in afresh, and page faults were much of a large upload's time in a profile.
    std::unique_ptr<GpuBuffer> staging;
    forEachSlab(dims, texelBytes, [&](int firstZ, int depth, vk::DeviceSize sliceBytes) {
        const vk::DeviceSize slabBytes = sliceBytes * static_cast<vk::DeviceSize>(depth);
        if (!staging) {
            staging = std::make_unique<GpuBuffer>(context, slabBytes, vk::BufferUsageFlagBits::eTransferSrc,
                                                  GpuBuffer::Memory::HostVisible, "volume upload staging");
        }
        fillSlab(firstZ, depth, static_cast<std::byte*>(staging->mapped()));
        const bool isLast = firstZ + depth == dims[2];
        submitAndWait(context, [&](const vk::raii::CommandBuffer& commands) {
            if (isFirst) recordImageBarrier(commands, image, vk::ImageLayout::eUndefined, vk::ImageLayout::eTransferDstOptimal);
            vk::BufferImageCopy region(0, 0, 0, vk::ImageSubresourceLayers(vk::ImageAspectFlagBits::eColor, 0, 0, 1),
                                       vk::Offset3D(0, 0, firstZ),
                                       vk::Extent3D(static_cast<uint32_t>(dims[0]), static_cast<uint32_t>(dims[1]),
                                                    static_cast<uint32_t>(depth)));
            commands.copyBufferToImage(*staging->buffer(), *image.image(), vk::ImageLayout::eTransferDstOptimal, region);
            if (isLast) {
                recordImageBarrier(commands, image, vk::ImageLayout::eTransferDstOptimal,
                                   vk::ImageLayout::eShaderReadOnlyOptimal);
            }
        });
        isFirst = false;
    });
}

vk::DeviceSize VolumeTexture::bytesFor(const std::array<int, 3>& dims) {
    vk::DeviceSize bytes = sizeof(uint16_t);
    for (const int n : dims) bytes *= static_cast<vk::DeviceSize>(std::max(n, 0));
    return bytes;
}

int VolumeTexture::slicesThatFit(const std::array<int, 3>& dims, vk::DeviceSize largestBytes) {
    const vk::DeviceSize sliceBytes = bytesFor({dims[0], dims[1], 1});
    if (sliceBytes == 0) return 0;
    return static_cast<int>(std::min<vk::DeviceSize>(largestBytes / sliceBytes, static_cast<vk::DeviceSize>(dims[2])));
}

VolumeTexture::VolumeTexture(const GpuContext& context, const volumes::Volume& volume)
    : mContext(&context),
      mDims(volume.dims),
      mSpacingMm(volume.spacingMm),
      mImage(context, extentOf(volume, context), vk::Format::eR16Unorm,
             vk::ImageUsageFlagBits::eSampled | vk::ImageUsageFlagBits::eTransferDst | vk::ImageUsageFlagBits::eTransferSrc,
             "CT volume", false, true),  // 3D even for one slice: the shaders read a sampler3D
      mSampler(context.device(), clampedSamplerInfo(vk::Filter::eLinear)) {
    volumes::validateVolume(volume, "volume for upload");
    uploadInSlabs(context, mImage, mDims, sizeof(uint16_t), [&](int firstZ, int depth, std::byte* staging) {
        auto* texels = reinterpret_cast<uint16_t*>(staging);
        const std::size_t first = volume.linearIndex(0, 0, firstZ);
        const std::size_t count = static_cast<std::size_t>(mDims[0]) * static_cast<std::size_t>(mDims[1]) *
                                  static_cast<std::size_t>(depth);
        for (std::size_t i = 0; i < count; ++i) {
            texels[i] = static_cast<uint16_t>(static_cast<int>(volume.hu[first + i]) + kHuTexelOffset);
        }
    });
}

std::vector<int16_t> VolumeTexture::readBackHu() const {
    std::vector<int16_t> hu(static_cast<std::size_t>(mDims[0]) * static_cast<std::size_t>(mDims[1]) *
                            static_cast<std::size_t>(mDims[2]));
    std::unique_ptr<GpuBuffer> buffer;  // one staging buffer, made for the first (the largest) slab
    forEachSlab(mDims, sizeof(uint16_t), [&](int firstZ, int depth, vk::DeviceSize sliceBytes) {
        const vk::DeviceSize slabBytes = sliceBytes * static_cast<vk::DeviceSize>(depth);
        if (!buffer || buffer->sizeBytes() < slabBytes) {
            buffer = std::make_unique<GpuBuffer>(*mContext, slabBytes, vk::BufferUsageFlagBits::eTransferDst,
                                                 GpuBuffer::Memory::HostVisible, "volume readback");
        }
        const GpuBuffer& readback = *buffer;
        submitAndWait(*mContext, [&](const vk::raii::CommandBuffer& commands) {
            recordImageBarrier(commands, mImage, vk::ImageLayout::eShaderReadOnlyOptimal, vk::ImageLayout::eTransferSrcOptimal);
            vk::BufferImageCopy region(0, 0, 0, vk::ImageSubresourceLayers(vk::ImageAspectFlagBits::eColor, 0, 0, 1),
                                       vk::Offset3D(0, 0, firstZ),
                                       vk::Extent3D(static_cast<uint32_t>(mDims[0]), static_cast<uint32_t>(mDims[1]),
                                                    static_cast<uint32_t>(depth)));
            commands.copyImageToBuffer(*mImage.image(), vk::ImageLayout::eTransferSrcOptimal, *readback.buffer(), region);
            recordImageBarrier(commands, mImage, vk::ImageLayout::eTransferSrcOptimal, vk::ImageLayout::eShaderReadOnlyOptimal);
        });
        const auto* texels = static_cast<const uint16_t*>(readback.mapped());
        const std::size_t first = static_cast<std::size_t>(sliceBytes / 2) * static_cast<std::size_t>(firstZ);
        const std::size_t count = static_cast<std::size_t>(sliceBytes / 2) * static_cast<std::size_t>(depth);
        for (std::size_t i = 0; i < count; ++i) hu[first + i] = static_cast<int16_t>(static_cast<int>(texels[i]) - kHuTexelOffset);
    });
    return hu;
}

}  // namespace engine
