/// @brief The small textures the ray caster samples besides the volume: the empty-space
/// distance map, the transfer-function table and the conformal map's cube map.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "engine/core/gpu_context.h"
#include "engine/core/gpu_image.h"
#include "engine/render/transfer_function.h"

namespace engine {

/// An image and the sampler it is read through.
struct SampledTexture {
    GpuImage image;
    vk::raii::Sampler sampler;
};

/// A sampler with `filter` (nearest or linear) that clamps to the edge along every axis, as every
/// texture of the ray caster is read.
vk::SamplerCreateInfo clampedSamplerInfo(vk::Filter filter);

/// The empty-space distance map (one byte per cell, see empty_space_map.h) as an R8_UINT 3D
/// image read with texelFetch.
SampledTexture makeSkipDistanceTexture(const GpuContext& context, const std::array<int, 3>& cellDims,
                                       const std::vector<uint8_t>& distances);

/// The transfer table as an n x 1 RGBA16 image with linear filtering, clamped at both ends.
SampledTexture makeTransferTexture(const GpuContext& context, const TransferTable& table);

/// A baked map (conformal::CubeMap's texels: 6 faces in Vulkan order of `size`^2 RGBA float
/// texels) as an RGBA32F cube image with linear filtering. Throws for a size that disagrees.
SampledTexture makeCubeMapTexture(const GpuContext& context, int size, std::span<const float> rgba);

/// A 1-texel cube map of the identity (every texel's RGB is its own direction): bound where a
/// pipeline bends no rays, since every declared binding needs a valid descriptor.
SampledTexture makeIdentityCubeMapTexture(const GpuContext& context);

}  // namespace engine
