/// @brief The gradient volume: each voxel's central differences, (v[i+1] - v[i-1]) / 2 along each
/// axis in HU per voxel, with neighbours beyond the volume clamped to its faces as the ray
/// caster's clamp-to-edge sampler clamps them, as an RGBA16F 3D image (alpha 0).
///
/// Why: shifting a trilinear fetch by exactly one voxel keeps its weights, so the six-fetch
/// central-difference gradient of the trilinear interpolant (shaders/volume_sampling.glsl)
/// equals these differences blended trilinearly, which is one fetch of this image; and the
/// 48-fetch B-spline gradient equals a B-spline blend of eight of its fetches. A shaded sample
/// then gets the same normal (but for half-float rounding, relative 2^-11) for far fewer fetches,
/// at 8 bytes a voxel of device memory, four times the volume's own.
#pragma once

#include <array>
#include <cstdint>

#include "engine/core/gpu_context.h"
#include "engine/render/sampled_textures.h"
#include "volumes/volume.h"

namespace engine {

/// The IEEE half-float bits of d / 2 for an integer |d| <= 65535 (the central difference of two
/// int16 voxels), rounded to nearest, ties to even: a normal half (0.5 <= |d / 2| <= 32767.5) or
/// zero. Throws std::invalid_argument outside that range.
[[nodiscard]] uint16_t halfFloatBitsOfHalf(int d);

/// Device bytes of the gradient volume of a volume of `dims` voxels.
[[nodiscard]] vk::DeviceSize gradientVolumeBytes(const std::array<int, 3>& dims);

/// Computes the gradient volume of `volume` on the host (all threads) and uploads it in slabs,
/// read through a trilinear clamp-to-edge sampler like the volume's own. Throws
/// DeviceMemoryError where the device cannot hold it.
SampledTexture makeGradientVolume(const GpuContext& context, const volumes::Volume& volume);

/// A 1x1x2 gradient volume of zeros: bound where a pipeline reads no gradient volume, since
/// every declared binding needs a valid descriptor.
SampledTexture makeEmptyGradientVolume(const GpuContext& context);

}  // namespace engine
