#include "colon/polyp_insertion.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "colon/colon_error.h"
#include "colon/volume_sampling.h"
#include "volumes/polyline.h"

namespace colon {
namespace {

/// Soft tissue (wall, fat under it, muscle) for the tissue value: excludes air, partial volume
/// next to air, tagged fluid and bone.
constexpr double kSoftTissueLowHu = -200.0;
constexpr double kSoftTissueHighHu = 300.0;
/// The tissue value is sampled this deep beneath the surface: clear of the partial-volume ramp,
/// still within a few millimetres of the wall (the air value the same distance above it).
constexpr double kSlabNearMm = 1.5;
constexpr double kSlabFarMm = 5.0;
/// The wall normal is fitted to the voxels within this many voxels (of the largest spacing) of the base.
constexpr double kNormalFitVoxels = 2.5;
/// A linear ramp of width e rises from 10% to 90% over 0.8 e (before sampling widens it).
constexpr double kRampTenToNinety = 0.8;

[[noreturn]] void fail(const std::string& problem) {
    throw ColonError("polyp insertion: " + problem);
}

std::string number(double value, int decimals = 1) {
    std::ostringstream out;
    out.setf(std::ios::fixed);
    out.precision(decimals);
    out << value;
    return out.str();
}

std::string pointText(const glm::dvec3& p) {
    std::ostringstream out;
    out.setf(std::ios::fixed);
    out.precision(1);
    out << '(' << p.x << ", " << p.y << ", " << p.z << ") mm";
    return out.str();
}

double largestSpacing(const volumes::Volume& volume) {
    return std::max({volume.spacingMm.x, volume.spacingMm.y, volume.spacingMm.z});
}

double smallestSpacing(const volumes::Volume& volume) {
    return std::min({volume.spacingMm.x, volume.spacingMm.y, volume.spacingMm.z});
}

/// A box of voxels, lo and hi inclusive.
struct VoxelRange {
    std::array<int, 3> lo{}, hi{};
};

/// The voxels whose centres lie in the box [minMm, maxMm], clipped to the grid.
VoxelRange voxelsAround(const volumes::Volume& volume, const glm::dvec3& minMm, const glm::dvec3& maxMm) {
    VoxelRange range;
    for (int a = 0; a < 3; ++a) {
        const auto axis = static_cast<std::size_t>(a);
        range.lo[axis] = std::max(0, static_cast<int>(std::ceil(minMm[a] / volume.spacingMm[a])));
        range.hi[axis] = std::min(volume.dims[axis] - 1, static_cast<int>(std::floor(maxMm[a] / volume.spacingMm[a])));
    }
    return range;
}

template <typename Visit>
void forEachVoxel(const VoxelRange& range, Visit&& visit) {
    for (int k = range.lo[2]; k <= range.hi[2]; ++k)
        for (int j = range.lo[1]; j <= range.hi[1]; ++j)
            for (int i = range.lo[0]; i <= range.hi[0]; ++i) visit(i, j, k);
}

glm::dvec3 centreOf(const volumes::Volume& volume, int i, int j, int k) {
    return glm::dvec3(i, j, k) * volume.spacingMm;
}

/// The HU gradient at a point: the slope of the linear function that fits the voxels within
/// `radiusMm` of it best (least squares, weights tapering smoothly to 0 at the radius so that
/// voxels entering or leaving the ball do not jolt it). Central differences of the trilinear HU
/// tilt the normal by 4 degrees on a sharp edge crossing the grid diagonally (the interpolated
/// iso surface is a staircase there); over a ball the fit's slope follows the edge's normal
/// whatever the profile across it, and it averages the scan's noise too.
glm::dvec3 huGradient(const volumes::Volume& volume, const glm::dvec3& pointMm, double radiusMm) {
    struct Sample {
        glm::dvec3 offset;
        double hu, weight;
    };
    std::vector<Sample> samples;
    glm::dvec3 meanOffset{0.0};
    double meanHu = 0.0, totalWeight = 0.0;
    forEachVoxel(voxelsAround(volume, pointMm - radiusMm, pointMm + radiusMm), [&](int i, int j, int k) {
        const glm::dvec3 offset = centreOf(volume, i, j, k) - pointMm;
        const double r2 = glm::dot(offset, offset) / (radiusMm * radiusMm);
        if (r2 >= 1.0) return;
        const double weight = (1.0 - r2) * (1.0 - r2);
        samples.push_back({offset, static_cast<double>(volume.at(i, j, k)), weight});
        meanOffset += weight * offset;
        meanHu += weight * volume.at(i, j, k);
        totalWeight += weight;
    });
    if (samples.size() < 4) return glm::dvec3(0.0);
    meanOffset /= totalWeight;
    meanHu /= totalWeight;
    glm::dmat3 covariance(0.0);
    glm::dvec3 correlation{0.0};
    for (const Sample& sample : samples) {
        const glm::dvec3 d = sample.offset - meanOffset;
        covariance += sample.weight * glm::outerProduct(d, d);
        correlation += sample.weight * (sample.hu - meanHu) * d;
    }
    if (std::abs(glm::determinant(covariance)) < 1e-12) return glm::dvec3(0.0);
    return glm::inverse(covariance) * correlation;
}

/// The point must be in the grid and in air: its nearest voxel below kLumenAirHu.
void requireLumenPoint(const volumes::Volume& volume, const glm::dvec3& pointMm) {
    if (!std::isfinite(pointMm.x) || !std::isfinite(pointMm.y) || !std::isfinite(pointMm.z)) {
        fail("the point is not finite");
    }
    std::array<int, 3> nearest{};
    for (int a = 0; a < 3; ++a) {
        const auto axis = static_cast<std::size_t>(a);
        const double index = std::round(pointMm[a] / volume.spacingMm[a]);
        if (index < 0.0 || index > volume.dims[axis] - 1) {
            const glm::dvec3 extent = glm::dvec3(volume.dims[0] - 1, volume.dims[1] - 1, volume.dims[2] - 1) *
                                      volume.spacingMm;
            fail("the point " + pointText(pointMm) + " is outside the volume (voxel centres span (0, 0, 0) to " +
                 pointText(extent) + ")");
        }
        nearest[axis] = static_cast<int>(index);
    }
    const int16_t hu = volume.at(nearest[0], nearest[1], nearest[2]);
    if (hu >= kLumenAirHu) {
        fail("the point " + pointText(pointMm) + " is not in the lumen (HU " + std::to_string(hu) +
             " at its nearest voxel; the lumen is air, below " + number(kLumenAirHu, 0) + " HU)");
    }
}

/// The centre of the voxel at or above `isoHu` nearest to the point, within kWallSearchMm.
glm::dvec3 nearestWallVoxel(const volumes::Volume& volume, const glm::dvec3& pointMm, double isoHu) {
    const VoxelRange range = voxelsAround(volume, pointMm - kWallSearchMm, pointMm + kWallSearchMm);
    double bestDistance2 = kWallSearchMm * kWallSearchMm;
    glm::dvec3 best{0.0};
    bool isFound = false;
    forEachVoxel(range, [&](int i, int j, int k) {
        if (volume.at(i, j, k) < isoHu) return;
        const glm::dvec3 centre = centreOf(volume, i, j, k);
        const glm::dvec3 offset = centre - pointMm;
        const double distance2 = glm::dot(offset, offset);
        if (distance2 <= bestDistance2) {
            bestDistance2 = distance2;
            best = centre;
            isFound = true;
        }
    });
    if (!isFound) {
        fail("no wall (HU at or above " + number(isoHu, 0) + ") within " + number(kWallSearchMm, 0) + " mm of " +
             pointText(pointMm));
    }
    return best;
}

/// The isoHu crossing on the segment from `airMm` (below iso) to `wallMm` (at or above), by bisection.
glm::dvec3 isoCrossing(const volumes::Volume& volume, glm::dvec3 airMm, glm::dvec3 wallMm, double isoHu) {
    for (int step = 0; step < 48; ++step) {
        const glm::dvec3 middle = 0.5 * (airMm + wallMm);
        (trilinearHu(volume, middle) < isoHu ? airMm : wallMm) = middle;
    }
    return 0.5 * (airMm + wallMm);
}

/// HU of the voxels whose centres lie between depths `nearMm` and `farMm` beneath the surface
/// (along -normal; negative depths are above it, in the lumen), within `radiusMm` of the normal
/// line through the surface point, and within [lowHu, highHu].
std::vector<double> slabValues(const volumes::Volume& volume, const glm::dvec3& surfaceMm, const glm::dvec3& normal,
                               double nearMm, double farMm, double radiusMm, double lowHu, double highHu) {
    const double reach = std::max({std::abs(nearMm), std::abs(farMm), radiusMm});
    std::vector<double> values;
    forEachVoxel(voxelsAround(volume, surfaceMm - reach, surfaceMm + reach), [&](int i, int j, int k) {
        const glm::dvec3 offset = centreOf(volume, i, j, k) - surfaceMm;
        const double depth = -glm::dot(offset, normal);
        if (depth < nearMm || depth > farMm) return;
        if (glm::length(offset + depth * normal) > radiusMm) return;
        const double hu = volume.at(i, j, k);
        if (hu >= lowHu && hu <= highHu) values.push_back(hu);
    });
    return values;
}

double median(std::vector<double> values) {
    const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
    std::nth_element(values.begin(), middle, values.end());
    return *middle;
}

/// Distance along `direction` from the surface to where a profile (`valueAt` a point) first
/// reaches `level` (rising to it when `isRising`, falling to it otherwise), interpolated
/// between samples; NaN when it does not within `reachMm`.
template <typename ValueAt>
double firstCrossingMm(const volumes::Volume& volume, const glm::dvec3& surfaceMm, const glm::dvec3& direction,
                       double level, bool isRising, double reachMm, ValueAt&& valueAt) {
    const double stepMm = 0.05 * smallestSpacing(volume);
    double previous = valueAt(surfaceMm);
    for (double t = stepMm; t <= reachMm; t += stepMm) {
        const double value = valueAt(surfaceMm + t * direction);
        if (isRising ? value >= level : value <= level) {
            const double fraction = value == previous ? 1.0 : (level - previous) / (value - previous);
            return t - stepMm + std::clamp(fraction, 0.0, 1.0) * stepMm;
        }
        previous = value;
    }
    return std::numeric_limits<double>::quiet_NaN();
}

/// The 10%-90% width across the surface of a profile going from `lowValue` in the lumen (along
/// `normal`) to `highValue` in the wall; NaN where it does not reach both within `reachMm`.
template <typename ValueAt>
double tenToNinetyMm(const volumes::Volume& volume, const glm::dvec3& surfaceMm, const glm::dvec3& normal,
                     double lowValue, double highValue, double reachMm, ValueAt&& valueAt) {
    const double contrast = highValue - lowValue;
    return firstCrossingMm(volume, surfaceMm, -normal, lowValue + 0.9 * contrast, true, reachMm, valueAt) +
           firstCrossingMm(volume, surfaceMm, normal, lowValue + 0.1 * contrast, false, reachMm, valueAt);
}

/// The ramp width (as the polyp is painted: w = clamp(0.5 - distance / width, 0, 1) at voxel
/// centres) whose trilinear profile across a plane through `surfaceMm` normal to `normal`, on
/// this grid, rises 10%-90% over `measuredMm`. Sampling at voxel centres and interpolating
/// widens a ramp, the more the coarser the grid and the more diagonal the plane (a 1.5 mm ramp
/// looks 1.7 mm wide at 1 mm voxels, 3.2 mm at 2 mm), so the scan's measured width is not the
/// ramp to paint: this undoes the widening the polyp will get too. At least `minimumMm`.
double matchingRampMm(const volumes::Volume& volume, const glm::dvec3& surfaceMm, const glm::dvec3& normal,
                      double measuredMm, double minimumMm, double reachMm) {
    const auto sampledWidth = [&](double rampMm) {
        const auto planeAt = [&](int i, int j, int k) {
            return std::clamp(0.5 - glm::dot(centreOf(volume, i, j, k) - surfaceMm, normal) / rampMm, 0.0, 1.0);
        };
        const double width = tenToNinetyMm(volume, surfaceMm, normal, 0.0, 1.0, reachMm, [&](const glm::dvec3& p) {
            return trilinear(volume, p, planeAt);
        });
        return std::isnan(width) ? std::numeric_limits<double>::max() : width;
    };
    if (sampledWidth(minimumMm) >= measuredMm) return minimumMm;
    // The sampled width grows with the ramp and is never less than the ramp's own 0.8 x width.
    double low = minimumMm, high = std::max(measuredMm / kRampTenToNinety, minimumMm);
    for (int step = 0; step < 30; ++step) {
        const double middle = 0.5 * (low + high);
        (sampledWidth(middle) < measuredMm ? low : high) = middle;
    }
    return 0.5 * (low + high);
}

/// What the scan looks like at the wall: its tissue and air values and its partial-volume blur.
struct WallSample {
    double tissueHu = 0.0, airHu = 0.0, blurMm = 0.0, edgeWidthMm = 0.0;
};

WallSample sampleWall(const volumes::Volume& volume, const glm::dvec3& surfaceMm, const glm::dvec3& normal,
                      double isoHu, double lumenHu) {
    // Wide enough for a dozen voxels even at 3 mm spacing.
    const double radiusMm = std::max(4.0, 2.0 * largestSpacing(volume));
    const std::vector<double> tissue =
        slabValues(volume, surfaceMm, normal, kSlabNearMm, kSlabFarMm, radiusMm, kSoftTissueLowHu, kSoftTissueHighHu);
    if (tissue.size() < 3) {
        fail("no soft tissue (" + number(kSoftTissueLowHu, 0) + ".." + number(kSoftTissueHighHu, 0) + " HU) " +
             number(kSlabNearMm) + ".." + number(kSlabFarMm) + " mm beneath the wall at " + pointText(surfaceMm) +
             " to take the polyp's value from");
    }
    WallSample wall;
    // Whole HU, so the inserted voxels (rounded) never exceed it.
    wall.tissueHu = std::round(median(tissue));
    const std::vector<double> air =
        slabValues(volume, surfaceMm, normal, -kSlabFarMm, -kSlabNearMm, radiusMm, -4096.0, isoHu);
    wall.airHu = air.empty() ? lumenHu : median(air);
    if (!(wall.airHu < isoHu && isoHu < wall.tissueHu)) {
        fail("the iso value " + number(isoHu, 0) + " HU is not between the lumen's " + number(wall.airHu, 0) +
             " HU and the wall's " + number(wall.tissueHu, 0) + " HU at " + pointText(surfaceMm));
    }
    // The scan's own blur: the 10%-90% rise of the profile across the surface, from the surface
    // into the wall and into the lumen.
    const double reachMm = std::max(10.0, 4.0 * largestSpacing(volume));
    const double measuredMm = tenToNinetyMm(volume, surfaceMm, normal, wall.airHu, wall.tissueHu, reachMm,
                                            [&](const glm::dvec3& p) { return trilinearHu(volume, p); });
    if (std::isnan(measuredMm)) {
        fail("the HU profile across the wall at " + pointText(surfaceMm) + " does not rise from 10% to 90% of " +
             number(wall.airHu, 0) + ".." + number(wall.tissueHu, 0) + " HU within " + number(reachMm, 0) +
             " mm either side; its edge width cannot be measured");
    }
    wall.blurMm = measuredMm;
    // A ramp narrower than half a voxel would alias: the grid cannot hold a sharper edge.
    wall.edgeWidthMm = matchingRampMm(volume, surfaceMm, normal, measuredMm, 0.5 * largestSpacing(volume), reachMm);
    return wall;
}

void requireSize(const volumes::Volume& volume, const PolypInsertion& request) {
    if (!std::isfinite(request.diameterMm) || request.diameterMm < kMinPolypDiameterMm ||
        request.diameterMm > kMaxPolypDiameterMm) {
        fail("polyp diameter " + number(request.diameterMm) + " mm is outside " + number(kMinPolypDiameterMm, 0) +
             ".." + number(kMaxPolypDiameterMm, 0) + " mm");
    }
    const double spacing = largestSpacing(volume);
    if (request.diameterMm < kMinPolypVoxelsAcross * spacing) {
        fail("the " + number(request.diameterMm) + " mm polyp is only " + number(request.diameterMm / spacing) +
             " voxels across at this scan's " + number(spacing, 2) + " mm spacing (the largest); it needs at least " +
             number(kMinPolypVoxelsAcross, 0) + ": a spacing of " + number(request.diameterMm / kMinPolypVoxelsAcross, 2) +
             " mm or less, or a diameter of " + number(kMinPolypVoxelsAcross * spacing) + " mm or more");
    }
    if (!std::isfinite(request.stalkLengthMm) || request.stalkLengthMm < 0.0) {
        fail("stalk length " + number(request.stalkLengthMm) + " mm must be 0 (sessile) or more");
    }
    if (!std::isfinite(request.isoHu)) fail("the iso value is not finite");
}

std::string describe(const PolypInsertion& request) {
    return request.stalkLengthMm > 0.0 ? "the " + number(request.diameterMm) + " mm pedunculated polyp on a " +
                                             number(request.stalkLengthMm) + " mm stalk"
                                       : "the " + number(request.diameterMm) + " mm sessile polyp";
}

/// The head (and its blur) must lie in the volume, and the lumen must be free of wall along the
/// normal from the base to the head's top, so the polyp does not run into the opposite wall.
void requireRoom(const volumes::Volume& volume, const PolypInsertion& request, const InsertedPolyp& polyp) {
    const volumes::PolypTruth& truth = polyp.truth;
    const double reach = truth.radiusMm + 0.5 * polyp.edgeWidthMm;
    const glm::dvec3 boxMax = (glm::dvec3(volume.dims[0], volume.dims[1], volume.dims[2]) - 0.5) * volume.spacingMm;
    const glm::dvec3 low = truth.centreMm - reach, high = truth.centreMm + reach;
    if (low.x < -0.5 * volume.spacingMm.x || low.y < -0.5 * volume.spacingMm.y || low.z < -0.5 * volume.spacingMm.z ||
        high.x > boxMax.x || high.y > boxMax.y || high.z > boxMax.z) {
        fail(describe(request) + " at " + pointText(truth.baseMm) + " would reach outside the volume");
    }
    const double topMm = glm::dot(truth.centreMm - truth.baseMm, truth.baseNormal) + reach;
    const double stepMm = 0.25 * smallestSpacing(volume);
    // From one edge width out: nearer, the profile is still the wall's own ramp.
    for (double t = polyp.edgeWidthMm; t <= topMm; t += stepMm) {
        const glm::dvec3 p = truth.baseMm + t * truth.baseNormal;
        if (trilinearHu(volume, p) >= request.isoHu) {
            fail(describe(request) + " would reach " + number(topMm) + " mm into the lumen from the wall at " +
                 pointText(truth.baseMm) + ", past the opposite wall " + number(t) + " mm away along the wall normal");
        }
    }
}

/// Raises every voxel of the polyp's box toward the tissue value by the polyp's partial volume.
std::size_t paintPolyp(volumes::Volume& volume, const InsertedPolyp& polyp) {
    const volumes::PolypTruth& truth = polyp.truth;
    glm::dvec3 low = truth.centreMm - truth.radiusMm, high = truth.centreMm + truth.radiusMm;
    if (polyp.stalkRadiusMm > 0.0) {
        low = glm::min(low, glm::min(polyp.stalkStartMm, polyp.stalkEndMm) - polyp.stalkRadiusMm);
        high = glm::max(high, glm::max(polyp.stalkStartMm, polyp.stalkEndMm) + polyp.stalkRadiusMm);
    }
    // w > 0 only within half an edge width outside the solid.
    const double margin = polyp.edgeWidthMm;
    std::size_t changed = 0;
    forEachVoxel(voxelsAround(volume, low - margin, high + margin), [&](int i, int j, int k) {
        const double w =
            std::clamp(0.5 - polyp.signedDistanceMm(centreOf(volume, i, j, k)) / polyp.edgeWidthMm, 0.0, 1.0);
        if (w == 0.0) return;
        int16_t& hu = volume.hu[volume.linearIndex(i, j, k)];
        if (hu >= polyp.tissueHu) return;  // the wall and anything denser stay as scanned
        const auto raised = static_cast<int16_t>(std::lround(hu + w * (polyp.tissueHu - hu)));
        if (raised == hu) return;
        hu = raised;
        ++changed;
    });
    return changed;
}

}  // namespace

double InsertedPolyp::signedDistanceMm(const glm::dvec3& pointMm) const {
    double distance = glm::length(pointMm - truth.centreMm) - truth.radiusMm;
    if (stalkRadiusMm > 0.0) {
        distance = std::min(distance, volumes::distanceToSegmentMm(pointMm, stalkStartMm, stalkEndMm) - stalkRadiusMm);
    }
    return distance;
}

InsertedPolyp insertPolyp(volumes::Volume& volume, const PolypInsertion& request) {
    requireLumenPoint(volume, request.atMm);
    requireSize(volume, request);
    const double pointHu = trilinearHu(volume, request.atMm);
    if (pointHu >= request.isoHu) {
        fail("the point " + pointText(request.atMm) + " lies on the wall (HU " + number(pointHu, 0) +
             " there); give a point further into the lumen");
    }

    // The wall surface nearest the point, and its normal into the lumen (HU rises into tissue).
    const glm::dvec3 wallVoxel = nearestWallVoxel(volume, request.atMm, request.isoHu);
    const glm::dvec3 baseMm = isoCrossing(volume, request.atMm, wallVoxel, request.isoHu);
    const glm::dvec3 gradient = huGradient(volume, baseMm, kNormalFitVoxels * largestSpacing(volume));
    if (!(glm::length(gradient) > 1e-9)) fail("the wall at " + pointText(baseMm) + " has no HU gradient");
    const glm::dvec3 normal = -glm::normalize(gradient);
    const glm::dvec3 towardPoint = request.atMm - baseMm;
    if (glm::length(towardPoint) > 0.5 * smallestSpacing(volume) && glm::dot(normal, towardPoint) <= 0.0) {
        fail("the wall at " + pointText(baseMm) + " faces away from the point (its HU rises toward the lumen)");
    }

    const WallSample wall = sampleWall(volume, baseMm, normal, request.isoHu, pointHu);
    InsertedPolyp polyp;
    polyp.tissueHu = wall.tissueHu;
    polyp.airHu = wall.airHu;
    polyp.wallBlurMm = wall.blurMm;
    polyp.edgeWidthMm = wall.edgeWidthMm;
    volumes::PolypTruth& truth = polyp.truth;
    truth.radiusMm = 0.5 * request.diameterMm;
    truth.baseMm = baseMm;
    truth.baseNormal = normal;
    if (request.stalkLengthMm > 0.0) {
        // As in the colon phantom: the head on a capsule stalk rooted just inside the wall.
        truth.kind = volumes::PolypKind::Pedunculated;
        truth.stalkLengthMm = request.stalkLengthMm;
        truth.centreMm = baseMm + (request.stalkLengthMm + truth.radiusMm) * normal;
        polyp.stalkStartMm = baseMm - 0.5 * polyp.edgeWidthMm * normal;
        polyp.stalkEndMm = truth.centreMm;
        polyp.stalkRadiusMm = std::max(1.0, 0.3 * truth.radiusMm);
    } else {
        truth.kind = volumes::PolypKind::Sessile;
        truth.centreMm = baseMm;  // half of the sphere in the lumen, half in the wall
    }
    requireRoom(volume, request, polyp);
    polyp.voxelsChanged = paintPolyp(volume, polyp);
    return polyp;
}

}  // namespace colon
