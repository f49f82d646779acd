#include "engine/render/gradient_volume.h"

#include <algorithm>
#include <bit>
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

uint16_t halfFloatBits(float value) {
    // Giesen's conversion ("float->half variants", 2016), a few integer operations where a
    // general one branches per case: the gradient volume converts three floats a voxel.
    constexpr uint32_t kOverflow = (127u + 16u) << 23;  // 2^16 and above round to infinity
    constexpr uint32_t kSmallestNormal = 113u << 23;    // 2^-14
    const auto subnormalMagic = std::bit_cast<float>(((127u - 15u) + (23u - 10u) + 1u) << 23);
    uint32_t bits = std::bit_cast<uint32_t>(value);
    const uint32_t sign = bits & 0x80000000u;
    bits ^= sign;
    uint32_t half = 0;
    if (bits >= kOverflow) {
        half = bits > (255u << 23) ? 0x7E00u : 0x7C00u;  // NaN stays NaN
    } else if (bits < kSmallestNormal) {
        // Adding the magic number lets the FPU round the subnormal into the low bits.
        half = std::bit_cast<uint32_t>(std::bit_cast<float>(bits) + subnormalMagic) -
               std::bit_cast<uint32_t>(subnormalMagic);
    } else {
        const uint32_t isOdd = (bits >> 13) & 1u;  // ties to even
        bits += (static_cast<uint32_t>(15 - 127) << 23) + 0xFFFu + isOdd;  // rebias, round (wraps by design)
        half = bits >> 13;
    }
    return static_cast<uint16_t>(half | (sign >> 16));
}

vk::DeviceSize gradientVolumeBytes(const std::array<int, 3>& dims) {
    vk::DeviceSize bytes = 4 * sizeof(uint16_t);
    for (const int n : dims) bytes *= static_cast<vk::DeviceSize>(std::max(n, 0));
    return bytes;
}

namespace {

/// A three-tap filter along x of each row of a plane (w[0] on x - 1, w[1] on x, w[2] on x + 1),
/// indices clamped to the row. The interior needs no clamping, so it vectorises.
void filterRows(const std::vector<float>& in, std::vector<float>& out, int nx, int ny, const float (&w)[3]) {
    for (int y = 0; y < ny; ++y) {
        const float* row = &in[static_cast<std::size_t>(y) * nx];
        float* result = &out[static_cast<std::size_t>(y) * nx];
        const auto clamped = [&](int x) { return row[std::clamp(x, 0, nx - 1)]; };
        result[0] = w[0] * clamped(-1) + w[1] * row[0] + w[2] * clamped(1);
        for (int x = 1; x + 1 < nx; ++x) result[x] = w[0] * row[x - 1] + w[1] * row[x] + w[2] * row[x + 1];
        if (nx > 1) result[nx - 1] = w[0] * row[nx - 2] + w[1] * row[nx - 1] + w[2] * clamped(nx);
    }
}

/// The same filter along y: each output row from the rows y - 1, y, y + 1, clamped to the plane.
void filterColumns(const std::vector<float>& in, std::vector<float>& out, int nx, int ny, const float (&w)[3]) {
    for (int y = 0; y < ny; ++y) {
        const float* below = &in[static_cast<std::size_t>(std::max(y - 1, 0)) * nx];
        const float* row = &in[static_cast<std::size_t>(y) * nx];
        const float* above = &in[static_cast<std::size_t>(std::min(y + 1, ny - 1)) * nx];
        float* result = &out[static_cast<std::size_t>(y) * nx];
        for (int x = 0; x < nx; ++x) result[x] = w[0] * below[x] + w[1] * row[x] + w[2] * above[x];
    }
}

}  // namespace

void bsplineGradientsOfSlice(const volumes::Volume& volume, int z, std::span<float> xyz) {
    const int nx = volume.dims[0], ny = volume.dims[1], nz = volume.dims[2];
    const std::size_t plane = static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny);
    if (z < 0 || z >= nz || xyz.size() != 3 * plane) {
        throw std::invalid_argument("slice " + std::to_string(z) + " or its " + std::to_string(xyz.size()) +
                                    " floats do not fit the volume");
    }
    // Each component is S_x S_y S_z D_k v: the central difference D_k along its axis and the
    // B-spline's (1 4 1) / 6 smoothing S along each axis, every tap clamped to the volume. Filters
    // along different axes commute, so the z filters combine whole slices first: P = S_z v, and
    // Q = S_z D_z v (up to five slices, their weights summed where clamping repeats one).
    constexpr float kSmooth[3] = {1.0f / 6.0f, 4.0f / 6.0f, 1.0f / 6.0f};
    constexpr float kDifference[3] = {-0.5f, 0.0f, 0.5f};
    const auto clampZ = [nz](int i) { return std::clamp(i, 0, nz - 1); };
    float sliceWeightP[3] = {0, 0, 0};        // on slices z - 1, z, z + 1
    float sliceWeightQ[5] = {0, 0, 0, 0, 0};  // on slices z - 2 .. z + 2
    for (int c = -1; c <= 1; ++c) {
        const int zc = clampZ(z + c);  // a clamped index stays within the window, so only slices in the volume get weight
        sliceWeightP[zc - z + 1] += kSmooth[c + 1];
        sliceWeightQ[clampZ(zc + 1) - z + 2] += kSmooth[c + 1] * kDifference[2];
        sliceWeightQ[clampZ(zc - 1) - z + 2] += kSmooth[c + 1] * kDifference[0];
    }
    // Scratch planes kept per thread: allocating them afresh for every slice would fault in new
    // pages each time, which cost 20 times the arithmetic here.
    thread_local std::vector<float> p, q, a, b, gx, gy, gz;
    for (std::vector<float>* scratch : {&p, &q, &a, &b, &gx, &gy, &gz}) scratch->resize(plane);
    std::fill(p.begin(), p.end(), 0.0f);
    std::fill(q.begin(), q.end(), 0.0f);
    const auto addSlice = [&](std::vector<float>& sum, int zs, float weight) {
        if (weight == 0.0f) return;
        const int16_t* slice = &volume.hu[volume.linearIndex(0, 0, zs)];
        for (std::size_t i = 0; i < plane; ++i) sum[i] += weight * static_cast<float>(slice[i]);
    };
    for (int k = 0; k < 3; ++k) addSlice(p, z - 1 + k, sliceWeightP[k]);
    for (int k = 0; k < 5; ++k) addSlice(q, z - 2 + k, sliceWeightQ[k]);
    filterRows(p, a, nx, ny, kDifference);  // S_y S_x D_x P
    filterRows(a, b, nx, ny, kSmooth);
    filterColumns(b, gx, nx, ny, kSmooth);
    filterColumns(p, a, nx, ny, kDifference);  // S_x S_y D_y P
    filterColumns(a, b, nx, ny, kSmooth);
    filterRows(b, gy, nx, ny, kSmooth);
    filterRows(q, a, nx, ny, kSmooth);  // S_x S_y Q
    filterColumns(a, gz, nx, ny, kSmooth);
    for (std::size_t i = 0; i < plane; ++i) {
        xyz[3 * i + 0] = gx[i];
        xyz[3 * i + 1] = gy[i];
        xyz[3 * i + 2] = gz[i];
    }
}

SampledTexture makeGradientVolume(const GpuContext& context, const volumes::Volume& volume,
                                  GradientVolumeContent content) {
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
    if (content == GradientVolumeContent::BSplineAtVoxels) {
        const std::size_t plane = static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny);
        uploadInSlabs(context, gradient.image, dims, 4 * sizeof(uint16_t), [&](int firstZ, int depth, std::byte* staging) {
            auto* texels = reinterpret_cast<uint16_t*>(staging);
            volumes::parallelFor(depth, [&](int slice) {
                thread_local std::vector<float> xyz;  // per thread, as the slice's own scratch
                xyz.resize(3 * plane);
                bsplineGradientsOfSlice(volume, firstZ + slice, xyz);
                uint16_t* out = texels + 4 * static_cast<std::size_t>(slice) * plane;
                for (std::size_t i = 0; i < plane; ++i) {
                    for (int k = 0; k < 3; ++k) out[4 * i + k] = halfFloatBits(xyz[3 * i + k]);
                    out[4 * i + 3] = 0;
                }
            });
        });
        return gradient;
    }
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
