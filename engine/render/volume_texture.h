/// @brief The CT volume on the device: an R16_UNORM 3D image holding HU + 32768, so every
/// int16 value survives exactly, sampled through a trilinear, clamp-to-edge sampler.
#pragma once

#include <functional>
#include <vector>

#include "engine/core/gpu_context.h"
#include "engine/core/gpu_image.h"
#include "volumes/volume.h"

namespace engine {

/// Offset that maps int16 HU onto the uint16 texel range (shaders undo it after sampling).
inline constexpr int kHuTexelOffset = 32768;

/// Uploads a 3D `image` of `dims` texels of `texelBytes` each, in z-slabs through at most 32 MiB
/// of staging memory: `fillSlab(firstZ, depth, texels)` writes the slab's texels (x fastest, then
/// y, then z) into the mapped staging memory. Leaves the image ready for sampling.
void uploadInSlabs(const GpuContext& context, const GpuImage& image, const std::array<int, 3>& dims,
                   vk::DeviceSize texelBytes, const std::function<void(int, int, std::byte*)>& fillSlab);

class VolumeTexture {
public:
    /// Uploads `volume` in slabs of at most 32 MiB, so the staging memory stays small next
    /// to a large CT. Throws if the device's 3D image limit is smaller than the volume, and
    /// DeviceMemoryError, saying how many slices would fit, if its memory cannot hold it.
    VolumeTexture(const GpuContext& context, const volumes::Volume& volume);

    /// Device bytes of a volume of `dims` voxels (16-bit texels).
    [[nodiscard]] static vk::DeviceSize bytesFor(const std::array<int, 3>& dims);
    /// How many of the volume's slices (along its third axis) fit in `largestBytes`.
    [[nodiscard]] static int slicesThatFit(const std::array<int, 3>& dims, vk::DeviceSize largestBytes);

    [[nodiscard]] const GpuImage& image() const { return mImage; }
    [[nodiscard]] const vk::raii::Sampler& sampler() const { return mSampler; }
    [[nodiscard]] std::array<int, 3> dims() const { return mDims; }
    [[nodiscard]] glm::dvec3 spacingMm() const { return mSpacingMm; }

    /// Copies the image back to the host as HU (for tests of the upload path).
    [[nodiscard]] std::vector<int16_t> readBackHu() const;

private:
    const GpuContext* mContext;
    std::array<int, 3> mDims;
    glm::dvec3 mSpacingMm;
    GpuImage mImage;
    vk::raii::Sampler mSampler;
};

}  // namespace engine
