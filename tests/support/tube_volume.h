/// @brief Synthetic colons for coverage tests: a straight air-filled tube along z with closed
/// ends, optional ring folds, and an optional pocket in its wall (a narrow neck out along +x
/// that turns into a chamber running along +z, so no point on the tube's axis can see into
/// it), and optional balls of tissue (polyps on the wall), as signed distances turned into HU
/// with a linear 1 mm ramp.
#pragma once

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "volumes/volume.h"

namespace testing_support {

struct TubeSpec {
    double spacingMm = 0.5;
    glm::dvec3 extentMm{32.0, 32.0, 80.0};
    double radiusMm = 8.0;
    double zStartMm = 8.0, zEndMm = 72.0;  // the closed ends
    // Ring folds: every foldSpacingMm from foldFirstMm to foldLastMm, reaching foldHeightMm in.
    double foldSpacingMm = 0.0;  // 0: no folds
    double foldFirstMm = 0.0, foldLastMm = 0.0;
    double foldHeightMm = 4.0, foldThicknessMm = 1.5;
    bool hasPocket = false;
    double pocketZMm = 40.0;  // the neck's centre along z
    // Balls of tissue (centre, radius in mm), e.g. centred on the wall: hemispherical polyps.
    std::vector<std::pair<glm::dvec3, double>> balls;
};

/// Box of half sizes `half` about `centre`: negative inside.
inline double boxDistance(const glm::dvec3& p, const glm::dvec3& centre, const glm::dvec3& half) {
    const glm::dvec3 q = glm::abs(p - centre) - half;
    return std::max({q.x, q.y, q.z});
}

struct PocketBoxes {
    glm::dvec3 neckCentre, neckHalf, chamberCentre, chamberHalf;
};

/// The pocket's two boxes in volume millimetres (the tube's axis at x = y = extent / 2; give the
/// volume 12 mm more along x for it).
inline PocketBoxes pocketBoxes(const TubeSpec& s) {
    const double cx = 0.5 * s.extentMm.x, cy = 0.5 * s.extentMm.y, R = s.radiusMm;
    PocketBoxes b;
    // Neck: 1.5 mm square, from inside the tube (R - 1) out to R + 6: a line through it from the
    // axis strays at most 1 : 4 from the radial direction.
    b.neckCentre = {cx + R + 2.5, cy, s.pocketZMm};
    b.neckHalf = {3.5, 0.75, 0.75};
    // Chamber: 3 mm deep beyond the neck, 4 mm wide, from the neck's -z side 18 mm along +z.
    b.chamberCentre = {cx + R + 7.5, cy, s.pocketZMm - 0.75 + 9.0};
    b.chamberHalf = {1.5, 2.0, 9.0};
    return b;
}

/// Signed distance to the air (negative in the lumen), in millimetres.
inline double lumenDistance(const TubeSpec& s, const glm::dvec3& p) {
    const double r = std::hypot(p.x - 0.5 * s.extentMm.x, p.y - 0.5 * s.extentMm.y);
    double d = std::max({r - s.radiusMm, s.zStartMm - p.z, p.z - s.zEndMm});
    if (s.foldSpacingMm > 0.0) {
        for (double z = s.foldFirstMm; z <= s.foldLastMm + 1e-9; z += s.foldSpacingMm) {
            const double fold = std::max(s.radiusMm - s.foldHeightMm - r, std::abs(p.z - z) - 0.5 * s.foldThicknessMm);
            d = std::max(d, -fold);
        }
    }
    for (const auto& [centre, radius] : s.balls) d = std::max(d, radius - glm::length(p - centre));
    if (s.hasPocket) {
        const PocketBoxes b = pocketBoxes(s);
        d = std::min({d, boxDistance(p, b.neckCentre, b.neckHalf), boxDistance(p, b.chamberCentre, b.chamberHalf)});
    }
    return d;
}

/// The tube as CT: -1000 HU air, +40 HU wall, a linear ramp 1 mm wide across the boundary.
inline volumes::Volume tubeVolume(const TubeSpec& s) {
    volumes::Volume v;
    for (int a = 0; a < 3; ++a) v.dims[static_cast<std::size_t>(a)] = static_cast<int>(std::lround(s.extentMm[a] / s.spacingMm));
    v.spacingMm = glm::dvec3(s.spacingMm);
    v.hu.resize(v.voxelCount());
    for (int k = 0; k < v.dims[2]; ++k) {
        for (int j = 0; j < v.dims[1]; ++j) {
            for (int i = 0; i < v.dims[0]; ++i) {
                const double d = lumenDistance(s, glm::dvec3(i, j, k) * s.spacingMm);
                const double t = std::clamp(0.5 + d, 0.0, 1.0);
                v.hu[v.linearIndex(i, j, k)] = static_cast<int16_t>(std::lround(-1000.0 + 1040.0 * t));
            }
        }
    }
    return v;
}

/// The lumen mask: voxels below -800 HU.
inline std::vector<uint8_t> airMask(const volumes::Volume& v) {
    std::vector<uint8_t> mask(v.hu.size());
    for (std::size_t n = 0; n < mask.size(); ++n) mask[n] = v.hu[n] < -800 ? 1 : 0;
    return mask;
}

}  // namespace testing_support
