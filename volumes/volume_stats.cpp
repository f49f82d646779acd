#include "volumes/volume_stats.h"

#include <cmath>
#include <limits>

namespace volumes {

std::string orientationCode(const Volume& volume) {
    static const char kPositive[3] = {'L', 'P', 'S'};
    static const char kNegative[3] = {'R', 'A', 'I'};
    std::string code;
    for (int axis = 0; axis < 3; ++axis) {
        const glm::dvec3 d = volume.directionLps[axis];
        int major = 0;
        for (int c = 1; c < 3; ++c) {
            if (std::abs(d[c]) > std::abs(d[major])) major = c;
        }
        code += d[major] >= 0.0 ? kPositive[major] : kNegative[major];
    }
    return code;
}

VolumeStats volumeStatsOf(const Volume& volume) {
    VolumeStats stats;
    stats.bins = {{"air", -32768, -900, 0},     {"lung", -900, -500, 0},         {"fat", -500, -30, 0},
                  {"soft tissue", -30, 150, 0}, {"contrast/bone", 150, 1000, 0}, {"dense bone/metal", 1000, 32768, 0}};
    if (volume.hu.empty()) return stats;
    std::vector<std::size_t> counts(65536, 0);
    double sum = 0.0;
    for (const int16_t v : volume.hu) {
        ++counts[static_cast<std::size_t>(static_cast<int>(v) + 32768)];
        sum += v;
    }
    stats.meanHu = sum / static_cast<double>(volume.hu.size());
    const std::array<double, 3> fractions{0.01, 0.5, 0.99};
    std::size_t seen = 0, nextPercentile = 0;
    bool hasMin = false;
    for (int hu = -32768; hu <= 32767; ++hu) {
        const std::size_t c = counts[static_cast<std::size_t>(hu + 32768)];
        if (c == 0) continue;
        if (!hasMin) {
            stats.minHu = static_cast<int16_t>(hu);
            hasMin = true;
        }
        stats.maxHu = static_cast<int16_t>(hu);
        seen += c;
        while (nextPercentile < fractions.size() &&
               static_cast<double>(seen) >= fractions[nextPercentile] * static_cast<double>(volume.hu.size())) {
            stats.percentileHu[nextPercentile++] = static_cast<int16_t>(hu);
        }
        for (HuBin& bin : stats.bins) {
            if (hu >= bin.lowHu && hu < bin.highHu) bin.count += c;
        }
    }
    return stats;
}

}  // namespace volumes
