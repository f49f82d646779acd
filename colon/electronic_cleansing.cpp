#include "colon/electronic_cleansing.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>

#include "colon/colon_error.h"

namespace colon {
namespace {

/// The grid axis closest to gravity and the sign of a step down it.
struct DownAxis {
    int axis = 1;
    int sign = 1;
};

DownAxis downAxisOf(const volumes::Volume& volume) {
    const glm::dvec3 g = gravityDirection(volume);
    DownAxis down;
    double best = -1.0;
    for (int a = 0; a < 3; ++a) {
        if (std::abs(g[a]) > best) {
            best = std::abs(g[a]);
            down.axis = a;
            down.sign = g[a] >= 0.0 ? 1 : -1;
        }
    }
    return down;
}

/// What the search has made of a voxel: a tagged voxel seen, a pool's fluid, a boundary voxel
/// unmixed (still wall, or now lumen).
enum Mark : uint8_t { kNone = 0, kVisited = 1, kFluid = 2, kEdge = 3, kEdgeLumen = 4 };

}  // namespace

glm::dvec3 gravityDirection(const volumes::Volume& volume) {
    // Volume millimetres map to LPS by directionLps (orthonormal): its transpose maps back.
    return glm::normalize(glm::transpose(volume.directionLps) * glm::dvec3(0.0, 1.0, 0.0));
}

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
    std::vector<uint8_t> mark(grid.voxelCount(), kNone);
    // Lumen: colon air, or a voxel this cleansing has made lumen.
    const auto isLumen = [&](std::size_t n) {
        const int32_t label = air.labels[n];
        return (label > 0 && isColonLabel[static_cast<std::size_t>(label)] != 0) || mark[n] == kFluid ||
               mark[n] == kEdgeLumen;
    };
    const DownAxis down = downAxisOf(volume);
    const auto downAxis = static_cast<std::size_t>(down.axis);
    const int gapVoxels = std::max(1, static_cast<int>(std::ceil(settings.levelGapMm / grid.spacingMm[down.axis])));
    const double voxelMl = grid.spacingMm.x * grid.spacingMm.y * grid.spacingMm.z / 1000.0;
    const auto maxPoolVoxels = static_cast<std::size_t>(settings.maxPoolMl / voxelMl);

    const auto isTagged = [&](std::size_t n) { return volume.hu[n] > settings.taggedHu; };
    // Colon air within the level gap above voxel (i, j, k) ("above": against gravity).
    const auto hasColonAirAbove = [&](std::array<int, 3> v) {
        for (int step = 1; step <= gapVoxels + 1; ++step) {
            v[downAxis] -= down.sign;
            if (!grid.contains(v[0], v[1], v[2])) return false;
            const std::size_t m = grid.index(v[0], v[1], v[2]);
            if (isLumen(m)) return true;
            if (isTagged(m)) return false;  // still inside tagged material: not the top surface
        }
        return false;
    };

    std::vector<std::size_t> pool;
    std::deque<std::size_t> frontier;
    // Seeds: tagged voxels just under colon air.
    for (std::size_t seed = 0; seed < mark.size(); ++seed) {
        if (mark[seed] != kNone || !isTagged(seed) || !hasColonAirAbove(grid.voxelOf(seed))) continue;
        // Grow the tagged region, measuring how much of its top surface meets colon air.
        pool.clear();
        frontier.assign(1, seed);
        mark[seed] = kVisited;
        std::size_t topVoxels = 0, topUnderAir = 0;
        bool isTooLarge = false;
        while (!frontier.empty()) {
            const std::size_t n = frontier.front();
            frontier.pop_front();
            pool.push_back(n);
            if (pool.size() > maxPoolVoxels) {
                isTooLarge = true;  // keep marking it visited, but stop growing
                break;
            }
            const auto v = grid.voxelOf(n);
            std::array<int, 3> upper = v;
            upper[downAxis] -= down.sign;
            const bool isTop = !grid.contains(upper[0], upper[1], upper[2]) ||
                               !isTagged(grid.index(upper[0], upper[1], upper[2]));
            if (isTop) {
                ++topVoxels;
                if (hasColonAirAbove(v)) ++topUnderAir;
            }
            const std::array<std::array<int, 3>, 6> steps{
                {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}}};
            for (const auto& s : steps) {
                const int a = v[0] + s[0], b = v[1] + s[1], c = v[2] + s[2];
                if (!grid.contains(a, b, c)) continue;
                const std::size_t m = grid.index(a, b, c);
                if (mark[m] != kNone || !isTagged(m)) continue;
                mark[m] = kVisited;
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
        // The pool's own value for the mix: its median (the ramp at its edges is a minority).
        std::vector<int16_t> values;
        values.reserve(pool.size());
        for (std::size_t n : pool) values.push_back(volume.hu[n]);
        std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2), values.end());
        const double fluidHu = std::max(static_cast<double>(values[values.size() / 2]), settings.taggedHu);
        for (std::size_t n : pool) mark[n] = kFluid;
        ++report.pools;
        report.fluidVoxels += pool.size();

        // Boundary layer: voxels within the level gap of the pool (a box around each voxel).
        const int r = gapVoxels;
        const auto isBetweenAirAndFluid = [&](std::size_t m, std::array<int, 3> v) {
            if (volume.hu[m] > fluidHu || !hasColonAirAbove(v)) return false;
            for (int step = 1; step <= r + 1; ++step) {
                v[downAxis] += down.sign;
                if (!grid.contains(v[0], v[1], v[2])) return false;
                if (mark[grid.index(v[0], v[1], v[2])] == kFluid) return true;
            }
            return false;
        };
        for (std::size_t n : pool) {
            const auto v = grid.voxelOf(n);
            for (int dk = -r; dk <= r; ++dk)
                for (int dj = -r; dj <= r; ++dj)
                    for (int di = -r; di <= r; ++di) {
                        const int a = v[0] + di, b = v[1] + dj, c = v[2] + dk;
                        if (!grid.contains(a, b, c)) continue;
                        const std::size_t m = grid.index(a, b, c);
                        if (mark[m] != kNone || isLumen(m)) continue;
                        const double h = volume.hu[m];
                        if (isBetweenAirAndFluid(m, std::array<int, 3>{a, b, c})) {
                            // Air-fluid level: lumen whatever the mix of the two.
                            volume.hu[m] = static_cast<int16_t>(std::lround(settings.airHu));
                            mark[m] = kEdgeLumen;
                            ++report.edgeVoxels;
                        } else if (h > settings.tissueHu) {
                            // Fluid-wall mix: the same fraction of air instead of fluid.
                            const double f = std::clamp((h - settings.tissueHu) / (fluidHu - settings.tissueHu), 0.0, 1.0);
                            volume.hu[m] = static_cast<int16_t>(
                                std::lround(settings.tissueHu + f * (settings.airHu - settings.tissueHu)));
                            mark[m] = f >= 0.5 ? kEdgeLumen : kEdge;
                            ++report.edgeVoxels;
                        }
                    }
        }
    }
    // The pools' fluid becomes air; the mask keeps what became lumen.
    for (std::size_t n = 0; n < mark.size(); ++n) {
        if (mark[n] == kFluid) volume.hu[n] = static_cast<int16_t>(std::lround(settings.airHu));
        mark[n] = mark[n] == kFluid || mark[n] == kEdgeLumen ? 1 : 0;
    }
    report.fluidMl = static_cast<double>(report.fluidVoxels) * voxelMl;
    return mark;
}

}  // namespace colon
