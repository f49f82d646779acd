/// @brief The map empty-space skipping reads: for every cell of a coarse grid over the volume,
/// how far it is to the nearest cell that can contribute, so a ray in empty space jumps that
/// far in one step.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace engine {

/// Largest distance stored; farther cells also read this (a byte per cell).
inline constexpr int kMaxSkipDistance = 255;

/// Chebyshev (chessboard) distance, in cells, from each cell to the nearest cell with
/// `isOccupied` set (0 for occupied cells), capped at kMaxSkipDistance. All cells c' with
/// max_i |c'_i - c_i| < d(c) are empty. Exact and separable, in time linear in the cells and
/// on all hardware threads: the distance along x, then the lower envelope of the chessboard
/// cones along y and z (Meijster, Roerdink and Hesselink 2000). Cells are x fastest over `dims`.
std::vector<uint8_t> chebyshevDistanceMap(const std::vector<uint8_t>& isOccupied, const std::array<int, 3>& dims);

}  // namespace engine
