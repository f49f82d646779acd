/// @brief How fast a baked map can turn a ray, region by region: a bound on the angle between
/// two scene directions over the angle between their display directions, for the map the
/// shader samples (bilinear between texels, normalised). The exact warp's empty-space skipping
/// divides its free distance by (1 + this bound) where the bound holds (shaders/raycast.comp).
#pragma once

#include <span>
#include <vector>

namespace conformal {

/// Each display direction's bound holds within this angle of it (radians): a ray whose
/// direction seen from the map centre stays this close to its final direction may use it.
inline constexpr double kSpeedBoundReachRadians = 0.1;

/// The coarse cube map of bounds: size^2 texels per face (Vulkan order), each RGBA = the bound
/// four times, so it can be uploaded and sampled like the map itself.
struct SpeedBoundMap {
    int size = 0;
    std::vector<float> rgba;
    double largest = 0.0;  ///< the largest bound anywhere (near the map's singular points)
};

/// Per fine texel, the largest angle ratio to its neighbours (along rows, columns and
/// diagonals, across face edges as seamless filtering reads them), times sqrt(2) for a
/// direction oblique to the texel grid, over the shortest interpolated vector's length; per
/// coarse texel, the largest of those within kSpeedBoundReachRadians plus two coarse texels'
/// width of its own directions, so a bilinear lookup anywhere is a bound for every direction
/// within kSpeedBoundReachRadians. `rgba` is a cube map's texels (size^2 RGBA per face, see
/// CubeMap). Throws std::invalid_argument for sizes below 2 or texels of the wrong count.
SpeedBoundMap speedBoundMap(int size, std::span<const float> rgba, int coarseSize = 32);

}  // namespace conformal
