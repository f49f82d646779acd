#include "engine/render/empty_space_map.h"

#include <algorithm>
#include <cstdlib>
#include <stdexcept>

#include "volumes/parallel_for.h"

namespace engine {
namespace {

// Distances are capped at kMaxSkipDistance at every stage, which leaves the capped result exact:
// a term the cap lowered was at least the cap, so it can lower no total below the cap.
constexpr int kCap = kMaxSkipDistance;

// One line of the second and third passes (Meijster, Roerdink and Hesselink, "A general algorithm
// for computing distance transforms in linear time", 2000, chessboard metric): given g, the
// distance already known within the line's orthogonal plane, writes
// out[x] = min over i of max(|x - i|, g[i]) in linear time. The lower envelope of the functions
// f_i(x) = max(|x - i|, g[i]) is built left to right: `owner` holds the indices whose function is
// lowest on a segment, `from` where that segment starts.
void chessboardLine(const int* g, int* out, int count, int* owner, int* from) {
    const auto f = [g](int x, int i) { return std::max(std::abs(x - i), g[i]); };
    // For i < u, the last x at which f_i <= f_u still holds (the paper's Sep for this metric):
    // from there on f_u is the lower one.
    const auto separation = [g](int i, int u) {
        return g[i] <= g[u] ? std::max(i + g[u], (i + u) / 2) : std::min(u - g[i], (i + u) / 2);
    };
    int top = 0;
    owner[0] = 0;
    from[0] = 0;
    for (int u = 1; u < count; ++u) {
        while (top >= 0 && f(from[top], owner[top]) > f(from[top], u)) --top;
        if (top < 0) {
            top = 0;
            owner[0] = u;
        } else {
            const int start = 1 + separation(owner[top], u);
            if (start < count) {
                ++top;
                owner[top] = u;
                from[top] = start;
            }
        }
    }
    for (int x = count - 1; x >= 0; --x) {
        out[x] = std::min(f(x, owner[top]), kCap);
        if (x == from[top]) --top;
    }
}

}  // namespace

std::vector<uint8_t> chebyshevDistanceMap(const std::vector<uint8_t>& isOccupied, const std::array<int, 3>& dims) {
    const std::size_t count = static_cast<std::size_t>(dims[0]) * static_cast<std::size_t>(dims[1]) *
                              static_cast<std::size_t>(dims[2]);
    if (dims[0] < 1 || dims[1] < 1 || dims[2] < 1 || isOccupied.size() != count) {
        throw std::invalid_argument("distance map: occupancy does not match the grid");
    }
    const int nx = dims[0], ny = dims[1], nz = dims[2];
    const std::size_t sliceSize = static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny);
    std::vector<uint8_t> d(count);

    // Passes 1 and 2, one z slice at a time: the distance along each x row (two scans), then the
    // chessboard envelope along each y column of the slice.
    volumes::parallelFor(nz, [&](int z) {
        const std::size_t slice = static_cast<std::size_t>(z) * sliceSize;
        std::vector<int> rows(sliceSize);
        for (int y = 0; y < ny; ++y) {
            int* row = rows.data() + static_cast<std::size_t>(y) * nx;
            const uint8_t* occupied = isOccupied.data() + slice + static_cast<std::size_t>(y) * nx;
            int last = kCap;
            for (int x = 0; x < nx; ++x) row[x] = last = occupied[x] ? 0 : std::min(last + 1, kCap);
            for (int x = nx - 2; x >= 0; --x) row[x] = std::min(row[x], row[x + 1] + 1);
        }
        std::vector<int> column(static_cast<std::size_t>(ny)), result(column.size()), owner(column.size()),
            from(column.size());
        for (int x = 0; x < nx; ++x) {
            for (int y = 0; y < ny; ++y) column[static_cast<std::size_t>(y)] = rows[static_cast<std::size_t>(y) * nx + x];
            chessboardLine(column.data(), result.data(), ny, owner.data(), from.data());
            for (int y = 0; y < ny; ++y) {
                d[slice + static_cast<std::size_t>(y) * nx + x] = static_cast<uint8_t>(result[static_cast<std::size_t>(y)]);
            }
        }
    });

    // Pass 3: the envelope along z, one y row of the grid per job (its buffers made once), in
    // blocks of neighbouring x (they share cache lines when the lines are gathered and written
    // back).
    constexpr int kBlock = 16;
    volumes::parallelFor(ny, [&](int y) {
        std::vector<int> lines(static_cast<std::size_t>(kBlock) * nz), result(static_cast<std::size_t>(nz)),
            owner(result.size()), from(result.size());
        for (int x0 = 0; x0 < nx; x0 += kBlock) {
            const int width = std::min(kBlock, nx - x0);
            const std::size_t base = static_cast<std::size_t>(y) * nx + x0;
            for (int z = 0; z < nz; ++z) {
                const uint8_t* source = d.data() + base + static_cast<std::size_t>(z) * sliceSize;
                for (int k = 0; k < width; ++k) lines[static_cast<std::size_t>(k) * nz + z] = source[k];
            }
            for (int k = 0; k < width; ++k) {
                chessboardLine(lines.data() + static_cast<std::size_t>(k) * nz, result.data(), nz, owner.data(), from.data());
                for (int z = 0; z < nz; ++z) {
                    d[base + static_cast<std::size_t>(z) * sliceSize + k] =
                        static_cast<uint8_t>(result[static_cast<std::size_t>(z)]);
                }
            }
        }
    });
    return d;
}

}  // namespace engine
