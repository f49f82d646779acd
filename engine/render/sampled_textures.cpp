#include "engine/render/sampled_textures.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace engine {

vk::SamplerCreateInfo clampedSamplerInfo(vk::Filter filter) {
    vk::SamplerCreateInfo info;
    info.magFilter = filter;
    info.minFilter = filter;
    info.mipmapMode = vk::SamplerMipmapMode::eNearest;
    info.addressModeU = info.addressModeV = info.addressModeW = vk::SamplerAddressMode::eClampToEdge;
    info.maxLod = 0.0f;
    return info;
}

namespace {

constexpr auto kSampledUsage = vk::ImageUsageFlagBits::eSampled | vk::ImageUsageFlagBits::eTransferDst;

}  // namespace

SampledTexture makeSkipDistanceTexture(const GpuContext& context, const std::array<int, 3>& cellDims,
                                       const std::vector<uint8_t>& distances) {
    const std::size_t count = static_cast<std::size_t>(cellDims[0]) * static_cast<std::size_t>(cellDims[1]) *
                              static_cast<std::size_t>(cellDims[2]);
    if (count == 0 || distances.size() != count) {
        throw std::invalid_argument("skip distance map holds " + std::to_string(distances.size()) + " cells, expected " +
                                    std::to_string(count));
    }
    // GpuImage makes a 3D image only for depth > 1: a one-cell-deep map gets a second layer,
    // a copy of the first, which the shader's clamped reads may see without harm.
    const uint32_t depth = static_cast<uint32_t>(std::max(cellDims[2], 2));
    std::vector<uint8_t> texels(distances);
    if (cellDims[2] == 1) texels.insert(texels.end(), distances.begin(), distances.end());
    SampledTexture texture{GpuImage(context,
                                    vk::Extent3D(static_cast<uint32_t>(cellDims[0]), static_cast<uint32_t>(cellDims[1]), depth),
                                    vk::Format::eR8Uint, kSampledUsage, "empty-space distance map"),
                           vk::raii::Sampler(context.device(), clampedSamplerInfo(vk::Filter::eNearest))};
    uploadImage(context, texture.image, std::as_bytes(std::span(texels)));
    return texture;
}

SampledTexture makeTransferTexture(const GpuContext& context, const TransferTable& table) {
    std::vector<uint16_t> texels;
    texels.reserve(table.rgba.size() * 4);
    for (const glm::vec4& entry : table.rgba) {
        for (int c = 0; c < 4; ++c) {
            texels.push_back(static_cast<uint16_t>(std::lround(std::clamp(entry[c], 0.0f, 1.0f) * 65535.0f)));
        }
    }
    SampledTexture texture{GpuImage(context, vk::Extent3D(static_cast<uint32_t>(table.rgba.size()), 1, 1),
                                    vk::Format::eR16G16B16A16Unorm, kSampledUsage, "transfer function"),
                           vk::raii::Sampler(context.device(), clampedSamplerInfo(vk::Filter::eLinear))};
    uploadImage(context, texture.image, std::as_bytes(std::span(texels)));
    return texture;
}

SampledTexture makeCubeMapTexture(const GpuContext& context, int size, std::span<const float> rgba) {
    if (size < 1 || size > 16384 ||
        rgba.size() != 6u * static_cast<std::size_t>(size) * static_cast<std::size_t>(size) * 4u) {
        throw std::invalid_argument("cube map of size " + std::to_string(size) + " holds " + std::to_string(rgba.size()) +
                                    " floats, expected 6 * size^2 * 4");
    }
    const auto edge = static_cast<uint32_t>(size);
    SampledTexture texture{GpuImage(context, vk::Extent3D(edge, edge, 1), vk::Format::eR32G32B32A32Sfloat, kSampledUsage,
                                    "conformal cube map", true),
                           vk::raii::Sampler(context.device(), clampedSamplerInfo(vk::Filter::eLinear))};
    uploadImage(context, texture.image, std::as_bytes(rgba));
    return texture;
}

SampledTexture makeIdentityCubeMapTexture(const GpuContext& context) {
    std::vector<float> rgba(24);
    const glm::vec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (int face = 0; face < 6; ++face) {
        for (int c = 0; c < 3; ++c) rgba[static_cast<std::size_t>(face * 4 + c)] = axes[face][c];
        rgba[static_cast<std::size_t>(face * 4 + 3)] = 1.0f;
    }
    return makeCubeMapTexture(context, 1, rgba);
}

}  // namespace engine
