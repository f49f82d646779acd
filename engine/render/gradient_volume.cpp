#include "engine/render/gradient_volume.h"

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include "engine/render/volume_texture.h"
#include "volumes/parallel_for.h"

namespace engine {
namespace {

constexpr vk::Format kGradientFormat = vk::Format::eR16G16B16A16Sfloat;  // filterable on every device
constexpr int kMaxDifference = 65535;  // |v[i+1] - v[i-1]| for int16 voxels

/// halfFloatBitsOfHalf for every difference, indexed by d + kMaxDifference (256 KiB, made once).
const std::vector<uint16_t>& halfTable() {
    static const std::vector<uint16_t> table = [] {
        std::vector<uint16_t> bits(2 * kMaxDifference + 1);
        for (int d = -kMaxDifference; d <= kMaxDifference; ++d) {
            bits[static_cast<std::size_t>(d + kMaxDifference)] = halfFloatBitsOfHalf(d);
        }
        return bits;
    }();
    return table;
}

}  // namespace

uint16_t halfFloatBitsOfHalf(int d) {
    if (d < -kMaxDifference || d > kMaxDifference) {
        throw std::invalid_argument("difference " + std::to_string(d) + " is outside +-65535");
    }
    const uint16_t sign = d < 0 ? uint16_t{0x8000} : uint16_t{0};
    auto magnitude = static_cast<uint32_t>(std::abs(d));
    if (magnitude == 0) return sign;
    int leading = 0;  // d / 2 = 1.f * 2^(leading - 1)
    while ((magnitude >> (leading + 1)) != 0) ++leading;
    uint32_t significand = 0;  // 11 bits: the leading one and 10 of fraction
    if (leading <= 10) {
        significand = magnitude << (10 - leading);
    } else {
        const int shift = leading - 10;
        significand = magnitude >> shift;
        const uint32_t rest = magnitude & ((1u << shift) - 1u);
        const uint32_t halfway = 1u << (shift - 1);
        if (rest > halfway || (rest == halfway && (significand & 1u) != 0)) ++significand;
        if (significand == (1u << 11)) {  // rounded up to the next power of two
            significand >>= 1;
            ++leading;
        }
    }
    const auto exponent = static_cast<uint32_t>(leading - 1 + 15);
    return static_cast<uint16_t>(sign | (exponent << 10) | (significand & 0x3FFu));
}

vk::DeviceSize gradientVolumeBytes(const std::array<int, 3>& dims) {
    vk::DeviceSize bytes = 4 * sizeof(uint16_t);
    for (const int n : dims) bytes *= static_cast<vk::DeviceSize>(std::max(n, 0));
    return bytes;
}

SampledTexture makeGradientVolume(const GpuContext& context, const volumes::Volume& volume) {
    volumes::validateVolume(volume, "volume for its gradient");
    const std::array<int, 3> dims = volume.dims;
    const vk::DeviceSize bytes = gradientVolumeBytes(dims);
    const vk::DeviceSize largest = context.largestAllocationBytes(vk::MemoryPropertyFlagBits::eDeviceLocal);
    if (bytes > largest) {
        throw DeviceMemoryError("the gradient volume needs " + mebibytesText(bytes) + " on the device, and " +
                                    context.deviceName() + " allows " + mebibytesText(largest) + " in one image",
                                largest);
    }
    const vk::Extent3D extent(static_cast<uint32_t>(dims[0]), static_cast<uint32_t>(dims[1]),
                              static_cast<uint32_t>(dims[2]));
    SampledTexture gradient{GpuImage(context, extent, kGradientFormat,
                                     vk::ImageUsageFlagBits::eSampled | vk::ImageUsageFlagBits::eTransferDst,
                                     "gradient volume", false, true),
                            vk::raii::Sampler(context.device(), clampedSamplerInfo(vk::Filter::eLinear))};
    const uint16_t* halfOf = halfTable().data() + kMaxDifference;  // halfOf[d]: the bits of d / 2
    const int nx = dims[0], ny = dims[1], nz = dims[2];
    uploadInSlabs(context, gradient.image, dims, 4 * sizeof(uint16_t), [&](int firstZ, int depth, std::byte* staging) {
        auto* texels = reinterpret_cast<uint16_t*>(staging);
        volumes::parallelFor(depth, [&](int slice) {
            const int z = firstZ + slice;
            const int zBelow = std::max(z - 1, 0), zAbove = std::min(z + 1, nz - 1);
            for (int y = 0; y < ny; ++y) {
                const int yBelow = std::max(y - 1, 0), yAbove = std::min(y + 1, ny - 1);
                const int16_t* row = &volume.hu[volume.linearIndex(0, y, z)];
                const int16_t* rowYBelow = &volume.hu[volume.linearIndex(0, yBelow, z)];
                const int16_t* rowYAbove = &volume.hu[volume.linearIndex(0, yAbove, z)];
                const int16_t* rowZBelow = &volume.hu[volume.linearIndex(0, y, zBelow)];
                const int16_t* rowZAbove = &volume.hu[volume.linearIndex(0, y, zAbove)];
                uint16_t* out = texels + 4 * (static_cast<std::size_t>(slice) * static_cast<std::size_t>(ny) + y) *
                                             static_cast<std::size_t>(nx);
                const auto write = [&](int x, int xBelow, int xAbove) {
                    out[4 * x + 0] = halfOf[row[xAbove] - row[xBelow]];
                    out[4 * x + 1] = halfOf[rowYAbove[x] - rowYBelow[x]];
                    out[4 * x + 2] = halfOf[rowZAbove[x] - rowZBelow[x]];
                    out[4 * x + 3] = 0;
                };
                write(0, 0, std::min(1, nx - 1));
                for (int x = 1; x + 1 < nx; ++x) write(x, x - 1, x + 1);  // the interior needs no clamping
                if (nx > 1) write(nx - 1, nx - 2, nx - 1);
            }
        });
    });
    return gradient;
}

SampledTexture makeEmptyGradientVolume(const GpuContext& context) {
    const std::vector<uint16_t> zeros(2 * 4, 0);  // two texels of four half floats, all +0
    SampledTexture gradient{GpuImage(context, vk::Extent3D(1, 1, 2), kGradientFormat,
                                     vk::ImageUsageFlagBits::eSampled | vk::ImageUsageFlagBits::eTransferDst,
                                     "no gradient volume", false, true),
                            vk::raii::Sampler(context.device(), clampedSamplerInfo(vk::Filter::eLinear))};
    uploadImage(context, gradient.image, std::as_bytes(std::span(zeros)));
    return gradient;
}

}  // namespace engine
