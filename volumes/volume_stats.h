/// @brief Summaries of a volume for people: orientation code, HU range, percentiles and a
/// histogram over the tissue classes a CT colonography reader cares about.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "volumes/volume.h"

namespace volumes {

/// Three letters naming the patient direction each grid axis points to most (L/R, P/A, S/I),
/// e.g. "LPS" for identity directions in LPS, "RAS" for a NIfTI-style grid.
std::string orientationCode(const Volume& volume);

/// One histogram bin: voxels with HU in [lowHu, highHu).
struct HuBin {
    std::string name;
    int lowHu = 0;
    int highHu = 0;
    std::size_t count = 0;
};

struct VolumeStats {
    int16_t minHu = 0;
    int16_t maxHu = 0;
    double meanHu = 0.0;
    /// HU at the 1st, 50th and 99th percentiles.
    std::array<int16_t, 3> percentileHu{0, 0, 0};
    /// Air (< -900), lung (-900..-500), fat (-500..-30), soft tissue (-30..150),
    /// contrast/bone (150..1000), dense bone and metal (>= 1000).
    std::vector<HuBin> bins;
};

/// Exact statistics in one pass (a 65536-entry count table; no copy of the voxels).
VolumeStats volumeStatsOf(const Volume& volume);

}  // namespace volumes
