#include "engine/render/empty_space_map.h"

#include <algorithm>
#include <stdexcept>

namespace engine {

std::vector<uint8_t> chebyshevDistanceMap(const std::vector<uint8_t>& isOccupied, const std::array<int, 3>& dims) {
    const std::size_t count = static_cast<std::size_t>(dims[0]) * static_cast<std::size_t>(dims[1]) *
                              static_cast<std::size_t>(dims[2]);
    if (dims[0] < 1 || dims[1] < 1 || dims[2] < 1 || isOccupied.size() != count) {
        throw std::invalid_argument("distance map: occupancy does not match the grid");
    }
    std::vector<uint8_t> d(count);
    for (std::size_t i = 0; i < count; ++i) d[i] = isOccupied[i] ? 0 : static_cast<uint8_t>(kMaxSkipDistance);
    const auto index = [&](int x, int y, int z) {
        return static_cast<std::size_t>(x) +
               static_cast<std::size_t>(dims[0]) * (static_cast<std::size_t>(y) + static_cast<std::size_t>(dims[1]) * z);
    };
    // One pass relaxes each cell from its 13 neighbours that come earlier in the pass's order.
    const auto pass = [&](int direction) {
        const int x0 = direction > 0 ? 0 : dims[0] - 1, x1 = direction > 0 ? dims[0] : -1;
        const int y0 = direction > 0 ? 0 : dims[1] - 1, y1 = direction > 0 ? dims[1] : -1;
        const int z0 = direction > 0 ? 0 : dims[2] - 1, z1 = direction > 0 ? dims[2] : -1;
        for (int z = z0; z != z1; z += direction) {
            for (int y = y0; y != y1; y += direction) {
                for (int x = x0; x != x1; x += direction) {
                    int best = d[index(x, y, z)];
                    if (best == 0) continue;
                    for (int dz = -1; dz <= 0; ++dz) {
                        for (int dy = -1; dy <= 1; ++dy) {
                            for (int dx = -1; dx <= 1; ++dx) {
                                // Earlier in raster order: a previous slice, or a previous row
                                // of this slice, or the previous cell of this row.
                                if (dz == 0 && (dy > 0 || (dy == 0 && dx >= 0))) continue;
                                const int nx = x + dx * direction, ny = y + dy * direction, nz = z + dz * direction;
                                if (nx < 0 || ny < 0 || nz < 0 || nx >= dims[0] || ny >= dims[1] || nz >= dims[2]) continue;
                                best = std::min(best, d[index(nx, ny, nz)] + 1);
                            }
                        }
                    }
                    d[index(x, y, z)] = static_cast<uint8_t>(std::min(best, kMaxSkipDistance));
                }
            }
        }
    };
    pass(+1);
    pass(-1);
    return d;
}

}  // namespace engine
