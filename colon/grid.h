/// @brief A dense voxel grid's shape and the index arithmetic every colon step shares: the
/// whole volume or a crop of it (a box of voxels with its offset in the volume).
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>

#include <glm/glm.hpp>

namespace colon {

struct Grid {
    std::array<int, 3> dims{0, 0, 0};
    glm::dvec3 spacingMm{1.0};

    [[nodiscard]] std::size_t voxelCount() const {
        return static_cast<std::size_t>(dims[0]) * static_cast<std::size_t>(dims[1]) *
               static_cast<std::size_t>(dims[2]);
    }
    [[nodiscard]] std::size_t index(int i, int j, int k) const {
        return static_cast<std::size_t>(i) +
               static_cast<std::size_t>(dims[0]) *
                   (static_cast<std::size_t>(j) + static_cast<std::size_t>(dims[1]) * static_cast<std::size_t>(k));
    }
    [[nodiscard]] std::array<int, 3> voxelOf(std::size_t n) const {
        const std::size_t layer = static_cast<std::size_t>(dims[0]) * static_cast<std::size_t>(dims[1]);
        const auto k = static_cast<int>(n / layer);
        const std::size_t rest = n % layer;
        return {static_cast<int>(rest % static_cast<std::size_t>(dims[0])),
                static_cast<int>(rest / static_cast<std::size_t>(dims[0])), k};
    }
    [[nodiscard]] bool contains(int i, int j, int k) const {
        return i >= 0 && j >= 0 && k >= 0 && i < dims[0] && j < dims[1] && k < dims[2];
    }
};

/// An axis-aligned box of voxels, lo and hi inclusive.
struct VoxelBox {
    std::array<int, 3> lo{0, 0, 0};
    std::array<int, 3> hi{-1, -1, -1};

    [[nodiscard]] bool isEmpty() const { return hi[0] < lo[0] || hi[1] < lo[1] || hi[2] < lo[2]; }
    void include(int i, int j, int k) {
        if (isEmpty()) {
            lo = hi = {i, j, k};
            return;
        }
        lo = {std::min(lo[0], i), std::min(lo[1], j), std::min(lo[2], k)};
        hi = {std::max(hi[0], i), std::max(hi[1], j), std::max(hi[2], k)};
    }
    /// The box grown by `margin` voxels on every side, clipped to `dims`.
    [[nodiscard]] VoxelBox grown(int margin, const std::array<int, 3>& dims) const {
        VoxelBox box;
        for (int a = 0; a < 3; ++a) {
            box.lo[static_cast<std::size_t>(a)] = std::max(0, lo[static_cast<std::size_t>(a)] - margin);
            box.hi[static_cast<std::size_t>(a)] =
                std::min(dims[static_cast<std::size_t>(a)] - 1, hi[static_cast<std::size_t>(a)] + margin);
        }
        return box;
    }
    [[nodiscard]] std::array<int, 3> size() const {
        return {hi[0] - lo[0] + 1, hi[1] - lo[1] + 1, hi[2] - lo[2] + 1};
    }
};

}  // namespace colon
