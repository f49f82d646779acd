/// @brief The gradient volume: a shading gradient per voxel, in HU per voxel along each axis, as an
/// RGBA16F 3D image (alpha 0), read through a trilinear clamp-to-edge sampler. It holds one of:
///
/// - each voxel's central differences, (v[i+1] - v[i-1]) / 2, with neighbours beyond the volume
///   clamped to its faces as the ray caster's clamp-to-edge sampler clamps them. Shifting a
///   trilinear fetch by exactly one voxel keeps its weights, so the six-fetch central-difference
///   gradient of the trilinear interpolant (shaders/volume_sampling.glsl) equals these
///   differences blended trilinearly, which is one fetch of this image; and the 48-fetch B-spline
///   gradient equals a B-spline blend of eight of its fetches. A shaded sample then gets the same
///   normal (but for half-float rounding, relative 2^-11) for far fewer fetches.
/// - the B-spline normals' gradient at each voxel's centre: those central differences smoothed by
///   the cubic B-spline's weights (1 4 1) / 6 along each axis, which is what the 48-fetch B-spline
///   gradient gives there. One fetch blends them trilinearly: the B-spline's smoothing (no
///   terraces on coarse CT) at the central differences' cost, with a kink in the normal's rate of
///   turn at voxel planes where the B-spline has none (docs/benchmarks/normals.md).
///
/// Either costs 8 bytes a voxel of device memory, four times the volume's own.
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include "engine/core/gpu_context.h"
#include "engine/render/sampled_textures.h"
#include "volumes/volume.h"

namespace engine {

/// The IEEE half-float bits of d / 2 for an integer |d| <= 65535 (the central difference of two
/// int16 voxels), rounded to nearest, ties to even: a normal half (0.5 <= |d / 2| <= 32767.5) or
/// zero. Throws std::invalid_argument outside that range.
[[nodiscard]] uint16_t halfFloatBitsOfHalf(int d);

/// The IEEE half-float bits nearest `value`, ties to even (subnormals included; 65520 and above
/// in magnitude give infinity, NaN a NaN).
[[nodiscard]] uint16_t halfFloatBits(float value);

/// What a gradient volume holds per voxel (the file comment above says why each).
enum class GradientVolumeContent { CentralDifferences, BSplineAtVoxels };

/// The B-spline normals' gradient at the voxel centres of slice `z` (HU per voxel, xyz per voxel,
/// x fastest): the central differences smoothed by (1 4 1) / 6 along each axis, every index
/// clamped to the volume as the sampler clamps it. `xyz` holds 3 * dims[0] * dims[1] floats.
void bsplineGradientsOfSlice(const volumes::Volume& volume, int z, std::span<float> xyz);

/// Device bytes of the gradient volume of a volume of `dims` voxels.
[[nodiscard]] vk::DeviceSize gradientVolumeBytes(const std::array<int, 3>& dims);

/// Computes the gradient volume of `volume` holding `content` on the host (all threads) and
/// uploads it in slabs, read through a trilinear clamp-to-edge sampler like the volume's own.
/// Throws DeviceMemoryError where the device cannot hold it.
SampledTexture makeGradientVolume(const GpuContext& context, const volumes::Volume& volume,
                                  GradientVolumeContent content = GradientVolumeContent::CentralDifferences);

/// A 1x1x2 gradient volume of zeros: bound where a pipeline reads no gradient volume, since
/// every declared binding needs a valid descriptor.
SampledTexture makeEmptyGradientVolume(const GpuContext& context);

}  // namespace engine
