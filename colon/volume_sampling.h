/// @brief Sampling a volume between voxel centres on the CPU, as the renderer's trilinear
/// filter does on the device: the HU a polyp's insertion, a wall's orientation or a hit's
/// surface are judged by.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>

#include <glm/glm.hpp>

#include "volumes/volume.h"

namespace colon {

/// Trilinear interpolation at a point in volume millimetres of `valueAt(i, j, k)`, a value per
/// voxel centre of `volume`'s grid, clamped at the grid's faces.
template <typename ValueAt>
double trilinear(const volumes::Volume& volume, const glm::dvec3& pointMm, ValueAt&& valueAt) {
    std::array<int, 3> lo{}, hi{};
    std::array<double, 3> fraction{};
    for (int a = 0; a < 3; ++a) {
        const auto axis = static_cast<std::size_t>(a);
        const int last = volume.dims[axis] - 1;
        const double g = std::clamp(pointMm[a] / volume.spacingMm[a], 0.0, static_cast<double>(last));
        lo[axis] = std::min(static_cast<int>(std::floor(g)), std::max(last - 1, 0));
        hi[axis] = std::min(lo[axis] + 1, last);
        fraction[axis] = g - lo[axis];
    }
    double sum = 0.0;
    for (int corner = 0; corner < 8; ++corner) {
        const bool x = (corner & 1) != 0, y = (corner & 2) != 0, z = (corner & 4) != 0;
        const double weight = (x ? fraction[0] : 1.0 - fraction[0]) * (y ? fraction[1] : 1.0 - fraction[1]) *
                              (z ? fraction[2] : 1.0 - fraction[2]);
        if (weight == 0.0) continue;
        sum += weight * valueAt(x ? hi[0] : lo[0], y ? hi[1] : lo[1], z ? hi[2] : lo[2]);
    }
    return sum;
}

/// The trilinear HU of `volume` at `pointMm`.
inline double trilinearHu(const volumes::Volume& volume, const glm::dvec3& pointMm) {
    return trilinear(volume, pointMm, [&](int i, int j, int k) { return static_cast<double>(volume.at(i, j, k)); });
}

}  // namespace colon
