#include "engine/sampled_textures.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace engine {
namespace {

vk::SamplerCreateInfo samplerInfo(vk::Filter filter) {
    vk::SamplerCreateInfo info;
    info.magFilter = filter;
    info.minFilter = filter;
    info.mipmapMode = vk::SamplerMipmapMode::eNearest;
    info.addressModeU = info.addressModeV = info.addressModeW = vk::SamplerAddressMode::eClampToEdge;
    info.maxLod = 0.0f;
    return info;
}

constexpr auto kSampledUsage = vk::ImageUsageFlagBits::eSampled | vk::ImageUsageFlagBits::eTransferDst;

}  // namespace

SampledTexture makeBrickOccupancyTexture(const GpuContext& context, const std::array<int, 3>& brickDims,
                                         const std::vector<uint8_t>& occupancy) {
    const std::size_t count = static_cast<std::size_t>(brickDims[0]) * static_cast<std::size_t>(brickDims[1]) *
                              static_cast<std::size_t>(brickDims[2]);
    if (count == 0 || occupancy.size() != count) {
        throw std::invalid_argument("brick occupancy holds " + std::to_string(occupancy.size()) + " bricks, expected " +
                                    std::to_string(count));
    }
    // A 3D image needs depth > 1 to be made 3D by GpuImage; a one-brick-deep volume is padded
    // with a second, empty layer that no sample can reach.
    const uint32_t depth = static_cast<uint32_t>(std::max(brickDims[2], 2));
    std::vector<uint8_t> texels(occupancy);
    texels.resize(count / static_cast<std::size_t>(brickDims[2]) * depth, 0);
    SampledTexture texture{GpuImage(context,
                                    vk::Extent3D(static_cast<uint32_t>(brickDims[0]), static_cast<uint32_t>(brickDims[1]), depth),
                                    vk::Format::eR8Uint, kSampledUsage, "brick occupancy"),
                           vk::raii::Sampler(context.device(), samplerInfo(vk::Filter::eNearest))};
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
                           vk::raii::Sampler(context.device(), samplerInfo(vk::Filter::eLinear))};
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
                           vk::raii::Sampler(context.device(), samplerInfo(vk::Filter::eLinear))};
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
