#include "colon/centreline.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <queue>

#include "colon/colon_error.h"
#include "colon/distance_transform.h"
#include "volumes/polyline.h"

namespace colon {
namespace {

constexpr float kUnreached = std::numeric_limits<float>::infinity();

/// A segment's crop: its voxels as a mask with one voxel of margin, and their wall distance.
struct Crop {
    Grid grid;
    std::array<int, 3> offset{0, 0, 0};
    std::vector<uint8_t> inside;
    std::vector<float> wallDistanceMm;

    [[nodiscard]] glm::dvec3 positionMm(std::size_t n) const {
        const auto v = grid.voxelOf(n);
        return glm::dvec3(v[0] + offset[0], v[1] + offset[1], v[2] + offset[2]) * grid.spacingMm;
    }
};

struct Neighbour {
    std::array<int, 3> step;
    float lengthMm;
};

std::vector<Neighbour> neighboursOf(const glm::dvec3& spacing) {
    std::vector<Neighbour> neighbours;
    for (int k = -1; k <= 1; ++k)
        for (int j = -1; j <= 1; ++j)
            for (int i = -1; i <= 1; ++i) {
                if (i == 0 && j == 0 && k == 0) continue;
                neighbours.push_back({{i, j, k}, static_cast<float>(glm::length(glm::dvec3(i, j, k) * spacing))});
            }
    return neighbours;
}

/// Single-source shortest paths over the crop's voxels; edge cost = length x weight(target).
/// Returns the distances; `previous` (if given) gets each voxel's predecessor.
template <typename Weight>
std::vector<float> shortestPaths(const Crop& crop, std::size_t source, Weight weight, std::vector<int64_t>* previous) {
    const auto neighbours = neighboursOf(crop.grid.spacingMm);
    std::vector<float> distance(crop.inside.size(), kUnreached);
    if (previous) previous->assign(crop.inside.size(), -1);
    using Entry = std::pair<float, std::size_t>;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
    distance[source] = 0.0f;
    queue.push({0.0f, source});
    while (!queue.empty()) {
        const auto [d, n] = queue.top();
        queue.pop();
        if (d > distance[n]) continue;
        const auto v = crop.grid.voxelOf(n);
        for (const Neighbour& neighbour : neighbours) {
            const int a = v[0] + neighbour.step[0], b = v[1] + neighbour.step[1], c = v[2] + neighbour.step[2];
            if (!crop.grid.contains(a, b, c)) continue;
            const std::size_t m = crop.grid.index(a, b, c);
            if (!crop.inside[m]) continue;
            const float candidate = d + neighbour.lengthMm * weight(m);
            if (candidate < distance[m]) {
                distance[m] = candidate;
                if (previous) (*previous)[m] = static_cast<int64_t>(n);
                queue.push({candidate, m});
            }
        }
    }
    return distance;
}

std::size_t farthestReached(const std::vector<float>& distance) {
    std::size_t best = 0;
    float bestDistance = -1.0f;
    for (std::size_t n = 0; n < distance.size(); ++n) {
        if (distance[n] != kUnreached && distance[n] > bestDistance) {
            bestDistance = distance[n];
            best = n;
        }
    }
    return best;
}

Crop cropOf(const Grid& grid, const std::vector<int32_t>& labels, int32_t label, const VoxelBox& segmentBox) {
    const VoxelBox box = segmentBox.grown(1, grid.dims);
    Crop crop;
    crop.offset = box.lo;
    crop.grid = Grid{box.size(), grid.spacingMm};
    crop.inside.assign(crop.grid.voxelCount(), 0);
    for (int k = 0; k < crop.grid.dims[2]; ++k)
        for (int j = 0; j < crop.grid.dims[1]; ++j)
            for (int i = 0; i < crop.grid.dims[0]; ++i) {
                const std::size_t n = grid.index(box.lo[0] + i, box.lo[1] + j, box.lo[2] + k);
                crop.inside[crop.grid.index(i, j, k)] = labels[n] == label ? 1 : 0;
            }
    crop.wallDistanceMm = distanceToOutsideMm(crop.grid, crop.inside);
    return crop;
}

/// The voxel of the crop nearest to a point in volume millimetres, or -1 outside the crop.
int64_t voxelAt(const Crop& crop, const glm::dvec3& pointMm) {
    const glm::dvec3 voxel = pointMm / crop.grid.spacingMm;
    const int i = static_cast<int>(std::lround(voxel.x)) - crop.offset[0];
    const int j = static_cast<int>(std::lround(voxel.y)) - crop.offset[1];
    const int k = static_cast<int>(std::lround(voxel.z)) - crop.offset[2];
    if (!crop.grid.contains(i, j, k)) return -1;
    return static_cast<int64_t>(crop.grid.index(i, j, k));
}

/// Whether a point in volume millimetres lies in the segment, at least `marginMm` from its wall
/// (by the wall distance of the nearest voxel).
bool isInside(const Crop& crop, const glm::dvec3& pointMm, double marginMm) {
    const int64_t n = voxelAt(crop, pointMm);
    if (n < 0) return false;
    const auto m = static_cast<std::size_t>(n);
    return crop.inside[m] != 0 && crop.wallDistanceMm[m] >= marginMm;
}

/// Rays cast around a centreline point to find the wall, and the weights of the robust fit.
constexpr int kWallRays = 48;
constexpr int kFitIterations = 8;

/// The centre of the circle that best fits the lumen's wall in the plane through `point`
/// normal to `tangent`, fitted robustly (Kasa's algebraic fit, reweighted by Tukey's biweight)
/// so that a polyp or a fold covering part of the circumference does not move it. None where
/// too few rays meet the wall within `searchMm` (the plane runs along the lumen at a bend) or
/// the fit is poor.
std::optional<glm::dvec3> fittedCentre(const Crop& crop, const glm::dvec3& point, const glm::dvec3& tangent,
                                       double searchMm, double voxelMm) {
    const glm::dvec3 helper = std::abs(tangent.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    const glm::dvec3 u = glm::normalize(glm::cross(tangent, helper));
    const glm::dvec3 v = glm::cross(tangent, u);
    const double stepMm = 0.25 * voxelMm;
    std::vector<glm::dvec2> wall;
    for (int ray = 0; ray < kWallRays; ++ray) {
        const double angle = 2.0 * 3.14159265358979323846 * ray / kWallRays;
        const glm::dvec2 direction(std::cos(angle), std::sin(angle));
        for (double r = stepMm; r <= searchMm; r += stepMm) {
            const int64_t n = voxelAt(crop, point + r * (direction.x * u + direction.y * v));
            if (n < 0 || crop.inside[static_cast<std::size_t>(n)] == 0) {
                wall.push_back((r - 0.5 * stepMm) * direction);
                break;
            }
        }
    }
    if (static_cast<int>(wall.size()) < kWallRays / 2) return std::nullopt;
    std::vector<double> weight(wall.size(), 1.0), residual(wall.size());
    glm::dvec2 centre{0.0};
    double radius = 0.0;
    for (int iteration = 0; iteration < kFitIterations; ++iteration) {
        // Minimise sum w (x^2 + y^2 + a x + b y + c)^2: 3x3 normal equations.
        glm::dmat3 normal(0.0);
        glm::dvec3 rhs(0.0);
        for (std::size_t k = 0; k < wall.size(); ++k) {
            const glm::dvec3 row(wall[k].x, wall[k].y, 1.0);
            const double target = -(wall[k].x * wall[k].x + wall[k].y * wall[k].y);
            normal += weight[k] * glm::outerProduct(row, row);
            rhs += weight[k] * target * row;
        }
        if (std::abs(glm::determinant(normal)) < 1e-12) return std::nullopt;
        const glm::dvec3 abc = glm::inverse(normal) * rhs;
        centre = glm::dvec2(-0.5 * abc.x, -0.5 * abc.y);
        const double r2 = glm::dot(centre, centre) - abc.z;
        if (!(r2 > 0.0)) return std::nullopt;
        radius = std::sqrt(r2);
        for (std::size_t k = 0; k < wall.size(); ++k) residual[k] = std::abs(glm::length(wall[k] - centre) - radius);
        std::vector<double> sorted = residual;
        std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2), sorted.end());
        const double scale = std::max(1.4826 * sorted[sorted.size() / 2], 0.25 * voxelMm);
        const double cutoff = 4.685 * scale;
        for (std::size_t k = 0; k < wall.size(); ++k) {
            const double x = residual[k] / cutoff;
            weight[k] = x < 1.0 ? (1.0 - x * x) * (1.0 - x * x) : 0.0;
        }
    }
    const auto inliers = std::count_if(weight.begin(), weight.end(), [](double w) { return w > 0.0; });
    if (inliers < kWallRays / 2 || glm::length(centre) > radius) return std::nullopt;
    return point + centre.x * u + centre.y * v;
}

/// Half the arc over which a point's tangent is taken (a chord across it).
constexpr double kTangentHalfWindowMm = 3.0;

std::vector<double> arcLengths(const std::vector<glm::dvec3>& points) {
    std::vector<double> arc(points.size(), 0.0);
    for (std::size_t i = 1; i < points.size(); ++i) arc[i] = arc[i - 1] + glm::length(points[i] - points[i - 1]);
    return arc;
}

/// The unit chord across +-halfWindowMm of arc around point i (zero if the points coincide).
glm::dvec3 tangentAt(const std::vector<glm::dvec3>& points, std::size_t i, double halfWindowMm) {
    const std::vector<double> arc = arcLengths(points);
    std::size_t lo = i, hi = i;
    while (lo > 0 && arc[i] - arc[lo] < halfWindowMm) --lo;
    while (hi + 1 < points.size() && arc[hi] - arc[i] < halfWindowMm) ++hi;
    const glm::dvec3 chord = points[hi] - points[lo];
    return glm::length(chord) > 0.0 ? glm::normalize(chord) : glm::dvec3(0.0);
}

/// Gaussian smoothing along the arc (sigma in mm); where a smoothed point would leave the
/// lumen it moves back toward the input point until it is inside.
std::vector<glm::dvec3> smoothAlongArc(const Crop& crop, const std::vector<glm::dvec3>& points, double sigma,
                                       double marginMm) {
    if (sigma <= 0.0) return points;
    const std::vector<double> arc = arcLengths(points);
    std::vector<glm::dvec3> smooth(points.size());
    std::size_t lo = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
        while (arc[i] - arc[lo] > 3.0 * sigma) ++lo;
        glm::dvec3 sum{0.0};
        double weights = 0.0;
        for (std::size_t j = lo; j < points.size() && arc[j] - arc[i] <= 3.0 * sigma; ++j) {
            const double x = (arc[j] - arc[i]) / sigma;
            const double w = std::exp(-0.5 * x * x);
            sum += w * points[j];
            weights += w;
        }
        glm::dvec3 point = sum / weights;
        for (int halving = 0; halving < 8 && !isInside(crop, point, marginMm); ++halving) point = 0.5 * (point + points[i]);
        if (!isInside(crop, point, marginMm)) point = points[i];
        smooth[i] = point;
    }
    return smooth;
}

/// The per-coordinate median over +-halfWindowMm of arc: drops isolated outliers, keeps steps.
std::vector<glm::dvec3> medianAlongArc(const std::vector<glm::dvec3>& points, double halfWindowMm) {
    const std::vector<double> arc = arcLengths(points);
    std::vector<glm::dvec3> out(points.size());
    std::size_t lo = 0;
    std::vector<double> window;
    for (std::size_t i = 0; i < points.size(); ++i) {
        while (arc[i] - arc[lo] > halfWindowMm) ++lo;
        std::size_t hi = i;
        while (hi + 1 < points.size() && arc[hi + 1] - arc[i] <= halfWindowMm) ++hi;
        for (int c = 0; c < 3; ++c) {
            window.clear();
            for (std::size_t j = lo; j <= hi; ++j) window.push_back(points[j][c]);
            std::nth_element(window.begin(), window.begin() + static_cast<std::ptrdiff_t>(window.size() / 2), window.end());
            out[i][c] = window[window.size() / 2];
        }
    }
    return out;
}

}  // namespace

SegmentCentreline centrelineOf(const Grid& grid, const std::vector<int32_t>& labels, int32_t label,
                               const VoxelBox& box, const CentrelineSettings& settings) {
    if (!(settings.smoothingMm >= 0.0) || !(settings.stepMm > 0.0)) {
        throw ColonError("centreline: smoothing must be non-negative and the step positive");
    }
    const Crop crop = cropOf(grid, labels, label, box);
    const std::size_t voxels = static_cast<std::size_t>(std::count(crop.inside.begin(), crop.inside.end(), uint8_t{1}));
    if (voxels < 3) return {};  // no path to speak of: the caller reports the segment as too short

    // 2. Endpoints: farthest from the most central voxel, then farthest from that.
    const std::size_t mostCentral = static_cast<std::size_t>(
        std::max_element(crop.wallDistanceMm.begin(), crop.wallDistanceMm.end()) - crop.wallDistanceMm.begin());
    const auto unit = [](std::size_t) { return 1.0f; };
    const std::size_t endA = farthestReached(shortestPaths(crop, mostCentral, unit, nullptr));
    const std::size_t endB = farthestReached(shortestPaths(crop, endA, unit, nullptr));

    // 3. The penalised path from A to B.
    const float maxDistance = crop.wallDistanceMm[mostCentral];
    std::vector<int64_t> previous;
    const auto penalty = [&](std::size_t n) {
        const float ratio = maxDistance / std::max(crop.wallDistanceMm[n], 1e-3f);
        return ratio * ratio;
    };
    shortestPaths(crop, endA, penalty, &previous);
    std::vector<std::size_t> voxelPath;
    for (int64_t n = static_cast<int64_t>(endB); n >= 0; n = previous[static_cast<std::size_t>(n)]) {
        voxelPath.push_back(static_cast<std::size_t>(n));
        if (voxelPath.size() > voxels) throw ColonError("centreline: path longer than its segment");  // cannot loop
    }
    std::reverse(voxelPath.begin(), voxelPath.end());

    // 4a. Trim the end caps: drop points nearer to their end (along the path) than the wall.
    std::vector<glm::dvec3> raw;
    std::vector<double> radius;
    for (std::size_t n : voxelPath) {
        raw.push_back(crop.positionMm(n));
        radius.push_back(crop.wallDistanceMm[n]);
    }
    const double voxel = std::max({grid.spacingMm.x, grid.spacingMm.y, grid.spacingMm.z});
    std::size_t first = 0, last = raw.size() - 1;
    for (double arc = 0.0; first + 1 < last && arc <= radius[first] + voxel; ++first)
        arc += glm::length(raw[first + 1] - raw[first]);
    for (double arc = 0.0; last > first + 1 && arc <= radius[last] + voxel; --last)
        arc += glm::length(raw[last] - raw[last - 1]);
    raw = std::vector<glm::dvec3>(raw.begin() + static_cast<std::ptrdiff_t>(first),
                                  raw.begin() + static_cast<std::ptrdiff_t>(last) + 1);
    radius = std::vector<double>(radius.begin() + static_cast<std::ptrdiff_t>(first),
                                 radius.begin() + static_cast<std::ptrdiff_t>(last) + 1);

    // 4b. Smooth the voxel staircase, then move each point to the centre of the circle fitted
    // to the wall around it (a polyp or a fold on one side pulls the distance ridge toward the
    // other; the fitted circle is the lumen's own), and smooth again: a running median first,
    // so that the few points where a fold fills most of the circumference do not show.
    const double margin = 0.5 * std::min({grid.spacingMm.x, grid.spacingMm.y, grid.spacingMm.z});
    const std::vector<glm::dvec3> smoothed = smoothAlongArc(crop, raw, settings.smoothingMm, margin);
    std::vector<glm::dvec3> centred = smoothed;
    for (std::size_t i = 0; i < smoothed.size(); ++i) {
        const glm::dvec3 tangent = tangentAt(smoothed, i, kTangentHalfWindowMm);
        if (glm::length(tangent) == 0.0) continue;
        const double searchMm = 2.5 * radius[std::min(i, radius.size() - 1)] + 2.0 * voxel;
        const auto centre = fittedCentre(crop, smoothed[i], tangent, searchMm, voxel);
        if (centre && isInside(crop, *centre, margin)) centred[i] = *centre;
    }
    const std::vector<glm::dvec3> path =
        smoothAlongArc(crop, medianAlongArc(centred, settings.smoothingMm), settings.smoothingMm, margin);

    SegmentCentreline centreline;
    centreline.pointsMm = volumes::resampleByArc(path, settings.stepMm);
    centreline.lengthMm = volumes::polylineLength(centreline.pointsMm);
    double sum = 0.0, minimum = std::numeric_limits<double>::max();
    for (double r : radius) {
        sum += r;
        minimum = std::min(minimum, r);
    }
    centreline.meanRadiusMm = sum / static_cast<double>(radius.size());
    centreline.minRadiusMm = minimum;
    return centreline;
}

}  // namespace colon
