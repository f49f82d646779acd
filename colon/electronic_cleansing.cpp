#include "colon/electronic_cleansing.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>

#include "colon/colon_error.h"

namespace colon {
namespace {

/// What the search has made of a voxel, as bits: a tagged voxel seen, one of a pool's voxels,
/// a voxel whose HU was rewritten, a voxel that became lumen.
enum Mark : uint8_t { kSeen = 1, kPool = 2, kDone = 4, kLumen = 8 };

}  // namespace

std::vector<uint8_t> cleanseTaggedFluid(volumes::Volume& volume, const AirSegmentation& air,
                                        const CleansingSettings& settings, CleansingReport& report) {
    if (!(settings.taggedHu > settings.tissueHu) || !(settings.levelGapMm > 0.0) || !(settings.maxPoolMl > 0.0)) {
        throw ColonError("cleansing: the tagged threshold must exceed the tissue value, the level gap be positive");
    }
    const Grid& grid = air.grid;
    report = CleansingReport{};
    // The colon's air, by region label (labels run 1..n).
    std::vector<uint8_t> isColonLabel(air.regions.size() + 1, 0);
    for (const AirRegion& region : air.regions) {
        isColonLabel[static_cast<std::size_t>(region.label)] = region.kind == AirClass::Colon ? 1 : 0;
    }
    std::vector<uint8_t> mark(grid.voxelCount(), 0);
    // The colon's air as the segmentation found it: never what this cleansing makes lumen, so
    // that the air-fluid level cannot creep down through a pool voxel by voxel.
    const auto isColonAir = [&](std::size_t n) {
        const int32_t label = air.labels[n];
        return label > 0 && isColonLabel[static_cast<std::size_t>(label)] != 0;
    };
    const VoxelAxis down = voxelAxisAlong(volume, kPosteriorLps);  // gravity, the patient supine
    const auto downAxis = static_cast<std::size_t>(down.axis);
    const int gapVoxels = std::max(1, static_cast<int>(std::ceil(settings.levelGapMm / grid.spacingMm[down.axis])));
    const double voxelMl = grid.spacingMm.x * grid.spacingMm.y * grid.spacingMm.z / 1000.0;
    const auto maxPoolVoxels = static_cast<std::size_t>(settings.maxPoolMl / voxelMl);

    const auto isTagged = [&](std::size_t n) { return volume.hu[n] > settings.taggedHu; };
    // Colon air within the level gap above voxel v ("above": against gravity), not through
    // tagged material (a voxel deep in a pool has fluid above it, not air).
    const auto hasColonAirAbove = [&](std::array<int, 3> v) {
        for (int step = 1; step <= gapVoxels + 1; ++step) {
            v[downAxis] -= down.sign;
            if (!grid.contains(v[0], v[1], v[2])) return false;
            const std::size_t m = grid.index(v[0], v[1], v[2]);
            if (isColonAir(m)) return true;
            if (isTagged(m)) return false;
        }
        return false;
    };
    // A pool voxel at v or within the level gap below it.
    const auto hasPoolAtOrBelow = [&](std::array<int, 3> v) {
        for (int step = 0; step <= gapVoxels + 1; ++step) {
            if (step > 0) v[downAxis] += down.sign;
            if (!grid.contains(v[0], v[1], v[2])) return false;
            if (mark[grid.index(v[0], v[1], v[2])] & kPool) return true;
        }
        return false;
    };

    std::vector<std::size_t> pool;
    std::deque<std::size_t> frontier;
    const std::array<std::array<int, 3>, 6> steps{{{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}}};
    // Seeds: tagged voxels just under colon air.
    for (std::size_t seed = 0; seed < mark.size(); ++seed) {
        if (mark[seed] != 0 || !isTagged(seed) || !hasColonAirAbove(grid.voxelOf(seed))) continue;
        // Grow the tagged region, measuring how much of its top surface meets colon air.
        pool.clear();
        frontier.assign(1, seed);
        mark[seed] = kSeen;
        std::size_t topVoxels = 0, topUnderAir = 0;
        bool isTooLarge = false;
        while (!frontier.empty()) {
            const std::size_t n = frontier.front();
            frontier.pop_front();
            pool.push_back(n);
            if (pool.size() > maxPoolVoxels) {
                isTooLarge = true;  // what it reached stays seen, so it is not grown again
                break;
            }
            const auto v = grid.voxelOf(n);
            std::array<int, 3> upper = v;
            upper[downAxis] -= down.sign;
            if (!grid.contains(upper[0], upper[1], upper[2]) || !isTagged(grid.index(upper[0], upper[1], upper[2]))) {
                ++topVoxels;
                if (hasColonAirAbove(v)) ++topUnderAir;
            }
            for (const auto& s : steps) {
                const int a = v[0] + s[0], b = v[1] + s[1], c = v[2] + s[2];
                if (!grid.contains(a, b, c)) continue;
                const std::size_t m = grid.index(a, b, c);
                if (mark[m] != 0 || !isTagged(m)) continue;
                mark[m] = kSeen;
                frontier.push_back(m);
            }
        }
        frontier.clear();
        const bool isPool = !isTooLarge && static_cast<double>(pool.size()) * voxelMl >= settings.minPoolMl &&
                            static_cast<double>(topUnderAir) >= settings.minSurfaceContact * static_cast<double>(topVoxels);
        if (!isPool) {
            ++report.rejectedRegions;
            continue;
        }
        // The pool's own value for the mix: its median (the ramps at its edges are a minority).
        std::vector<int16_t> values;
        values.reserve(pool.size());
        for (std::size_t n : pool) values.push_back(volume.hu[n]);
        std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2), values.end());
        const double fluidHu = std::max(static_cast<double>(values[values.size() / 2]), settings.taggedHu);
        for (std::size_t n : pool) mark[n] |= kPool;
        ++report.pools;
        report.fluidVoxels += pool.size();

        // Rewrite the pool and every voxel within the level gap of it (a box around each pool
        // voxel), each once: the air-fluid level becomes air; a fluid-wall mix becomes the same
        // mix of air and wall; the rest (wall beyond the fluid's reach) stays.
        const int r = gapVoxels;
        for (std::size_t n : pool) {
            const auto v = grid.voxelOf(n);
            for (int dk = -r; dk <= r; ++dk)
                for (int dj = -r; dj <= r; ++dj)
                    for (int di = -r; di <= r; ++di) {
                        const std::array<int, 3> w{v[0] + di, v[1] + dj, v[2] + dk};
                        if (!grid.contains(w[0], w[1], w[2])) continue;
                        const std::size_t m = grid.index(w[0], w[1], w[2]);
                        if ((mark[m] & kDone) || isColonAir(m)) continue;
                        const double h = volume.hu[m];
                        if (hasColonAirAbove(w) && hasPoolAtOrBelow(w)) {
                            volume.hu[m] = static_cast<int16_t>(std::lround(settings.airHu));
                            mark[m] |= kDone | kLumen;
                        } else if (h > settings.tissueHu) {
                            const double f = std::clamp((h - settings.tissueHu) / (fluidHu - settings.tissueHu), 0.0, 1.0);
                            volume.hu[m] = static_cast<int16_t>(
                                std::lround(settings.tissueHu + f * (settings.airHu - settings.tissueHu)));
                            mark[m] |= f >= 0.5 ? kDone | kLumen : kDone;
                        } else {
                            continue;  // wall or fat: not touched, and not counted
                        }
                        if (!(mark[m] & kPool)) ++report.edgeVoxels;
                    }
        }
    }
    for (uint8_t& m : mark) m = (m & kLumen) ? 1 : 0;
    report.fluidMl = static_cast<double>(report.fluidVoxels) * voxelMl;
    return mark;
}

}  // namespace colon
