#include "colon/lumen_segmentation.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>

#include "colon/colon_error.h"
#include "colon/connected_components.h"
#include "colon/distance_transform.h"

namespace colon {
namespace {

constexpr double kPi = 3.14159265358979323846;
/// HU histogram range for the regions' medians (air and lung only reach this far).
constexpr int kHistogramLowHu = -1024, kHistogramHighHu = 0;

Grid gridOf(const volumes::Volume& volume) { return Grid{volume.dims, volume.spacingMm}; }

double voxelMl(const Grid& grid) { return grid.spacingMm.x * grid.spacingMm.y * grid.spacingMm.z / 1000.0; }

bool touchesSide(const VoxelBox& box, const Grid& grid, int headFoot) {
    for (int a = 0; a < 3; ++a) {
        if (a == headFoot) continue;
        const auto axis = static_cast<std::size_t>(a);
        if (box.lo[axis] == 0 || box.hi[axis] == grid.dims[axis] - 1) return true;
    }
    return false;
}

/// Median HU and centroid of region `label`, read over its bounding box.
void measureValues(const volumes::Volume& volume, const AirSegmentation& air, AirRegion& region) {
    std::array<std::size_t, kHistogramHighHu - kHistogramLowHu + 1> histogram{};
    glm::dvec3 sum{0.0};
    for (int k = region.box.lo[2]; k <= region.box.hi[2]; ++k)
        for (int j = region.box.lo[1]; j <= region.box.hi[1]; ++j)
            for (int i = region.box.lo[0]; i <= region.box.hi[0]; ++i) {
                const std::size_t n = air.grid.index(i, j, k);
                if (air.labels[n] != region.label) continue;
                const int hu = std::clamp<int>(volume.hu[n], kHistogramLowHu, kHistogramHighHu);
                ++histogram[static_cast<std::size_t>(hu - kHistogramLowHu)];
                sum += glm::dvec3(i, j, k) * volume.spacingMm;
            }
    region.centroidMm = sum / static_cast<double>(region.voxels);
    std::size_t seen = 0;
    for (std::size_t b = 0; b < histogram.size(); ++b) {
        seen += histogram[b];
        if (2 * seen >= region.voxels) {
            region.medianHu = static_cast<double>(kHistogramLowHu) + static_cast<double>(b);
            break;
        }
    }
}

/// Largest inscribed radius and tubularity of region `label`, from the distance transform of
/// its bounding box (one voxel of margin, so the box's border is outside).
void measureShape(const AirSegmentation& air, AirRegion& region) {
    const VoxelBox box = region.box.grown(1, air.grid.dims);
    const auto size = box.size();
    Grid crop{size, air.grid.spacingMm};
    std::vector<uint8_t> inside(crop.voxelCount(), 0);
    for (int k = 0; k < size[2]; ++k)
        for (int j = 0; j < size[1]; ++j)
            for (int i = 0; i < size[0]; ++i) {
                const std::size_t n = air.grid.index(box.lo[0] + i, box.lo[1] + j, box.lo[2] + k);
                inside[crop.index(i, j, k)] = air.labels[n] == region.label ? 1 : 0;
            }
    const std::vector<float> distance = distanceToOutsideMm(crop, inside);
    // The distance to the nearest outside voxel centre overstates the radius by half a voxel
    // (the wall lies between the centres); the smallest spacing is the conservative half.
    const double halfVoxel = 0.5 * std::min({crop.spacingMm.x, crop.spacingMm.y, crop.spacingMm.z});
    region.maxRadiusMm = std::max(halfVoxel, *std::max_element(distance.begin(), distance.end()) - halfVoxel);
    const double volumeMm3 = region.volumeMl * 1000.0;
    region.tubularity = volumeMm3 / (2.0 * kPi * std::pow(region.maxRadiusMm, 3.0));
}

}  // namespace

const char* airClassName(AirClass kind) {
    switch (kind) {
        case AirClass::Outside: return "outside";
        case AirClass::Small: return "small";
        case AirClass::Lung: return "lung";
        case AirClass::Round: return "round";
        case AirClass::Colon: return "colon";
    }
    return "unknown";
}

VoxelAxis voxelAxisAlong(const volumes::Volume& volume, const glm::dvec3& directionLps) {
    const glm::dvec3 d = volumes::volumeDirectionFromPatient(volume, directionLps);
    VoxelAxis best;
    double bestWeight = -1.0;
    for (int a = 0; a < 3; ++a) {
        if (std::abs(d[a]) > bestWeight) {
            bestWeight = std::abs(d[a]);
            best = {a, d[a] >= 0.0 ? 1 : -1};
        }
    }
    return best;
}

AirSegmentation segmentAir(const volumes::Volume& volume, const SegmentationSettings& settings) {
    if (!std::isfinite(settings.airThresholdHu) || settings.airThresholdHu < -1024.0 || settings.airThresholdHu > 0.0) {
        throw ColonError("air threshold must be in -1024..0 HU");
    }
    if (!(settings.minRegionMl >= 0.0) || !(settings.minTubularity >= 0.0) || !std::isfinite(settings.lungMedianHu)) {
        throw ColonError("region size and tubularity limits must be non-negative, the lung limit finite");
    }
    AirSegmentation air;
    air.grid = gridOf(volume);
    air.labels.resize(volume.voxelCount());
    for (std::size_t n = 0; n < air.labels.size(); ++n) {
        air.labels[n] = volume.hu[n] < settings.airThresholdHu ? kUnlabelled : 0;
    }
    const std::vector<Component> components = labelComponents(air.grid, air.labels);
    const int headFoot = voxelAxisAlong(volume, kSuperiorLps).axis;
    const double ml = voxelMl(air.grid);
    for (const Component& component : components) {
        AirRegion region;
        region.label = component.label;
        region.voxels = component.voxels;
        region.volumeMl = static_cast<double>(component.voxels) * ml;
        region.box = component.box;
        if (touchesSide(region.box, air.grid, headFoot)) {
            region.kind = AirClass::Outside;
        } else if (region.volumeMl < settings.minRegionMl) {
            region.kind = AirClass::Small;
        } else {
            measureValues(volume, air, region);
            if (region.medianHu > settings.lungMedianHu) {
                region.kind = AirClass::Lung;
            } else {
                measureShape(air, region);
                region.kind = region.tubularity < settings.minTubularity ? AirClass::Round : AirClass::Colon;
            }
        }
        air.regions.push_back(region);
    }
    std::sort(air.regions.begin(), air.regions.end(),
              [](const AirRegion& a, const AirRegion& b) { return a.voxels > b.voxels; });
    return air;
}

void requireColon(const AirSegmentation& air, const SegmentationSettings& settings) {
    if (std::any_of(air.regions.begin(), air.regions.end(), [](const AirRegion& r) { return r.kind == AirClass::Colon; }))
        return;
    std::ostringstream message;
    message << "no air-filled colon found";
    if (air.regions.empty()) {
        message << ": the volume has no air (no voxel below " << settings.airThresholdHu << " HU)";
    } else if (air.regions.front().voxels == air.grid.voxelCount()) {
        message << ": the volume is air everywhere";
    } else {
        std::array<int, 5> counts{};
        for (const AirRegion& r : air.regions) ++counts[static_cast<std::size_t>(r.kind)];
        message << " among " << air.regions.size() << " air regions (" << counts[0] << " outside the body, " << counts[1]
                << " under " << settings.minRegionMl << " mL, " << counts[2] << " lung-like, " << counts[3]
                << " round); a CT colonography scan needs an insufflated colon";
    }
    throw ColonError(message.str());
}

}  // namespace colon
