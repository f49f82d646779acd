#include "colon/surface_measure.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <optional>
#include <string>

#include "colon/colon_error.h"

namespace colon {
namespace {

std::string pixelName(int x, int y) { return "(" + std::to_string(x) + ", " + std::to_string(y) + ")"; }

const glm::dvec3& requireHit(const HitImage& image, int x, int y) {
    if (!image.contains(x, y)) {
        throw ColonError("pixel " + pixelName(x, y) + " lies outside the " + std::to_string(image.width) + "x" +
                         std::to_string(image.height) + " hit image");
    }
    if (!image.hitAt(x, y)) throw ColonError("pixel " + pixelName(x, y) + " is a miss: its ray hit no surface");
    return image.hitMm[image.index(x, y)];
}

/// The local pixel footprint of rule 1 (see the header); 0 for an isolated hit.
double footprint(const HitImage& image, int x, int y) {
    const glm::dvec3& h = image.hitMm[image.index(x, y)];
    double largest = 0.0;
    for (int axis = 0; axis < 2; ++axis) {
        double shortest = -1.0;
        for (int sign : {-1, 1}) {
            const int qx = x + (axis == 0 ? sign : 0), qy = y + (axis == 1 ? sign : 0);
            if (!image.hitAt(qx, qy)) continue;
            const double step = glm::length(image.hitMm[image.index(qx, qy)] - h);
            if (shortest < 0.0 || step < shortest) shortest = step;
        }
        largest = std::max(largest, shortest);
    }
    return largest;
}

/// Rule 1: q is a hit continuous with p.
bool continuous(const HitImage& image, int px, int py, int qx, int qy, double footprintP) {
    if (!image.hitAt(qx, qy)) return false;
    return glm::length(image.hitMm[image.index(qx, qy)] - image.hitMm[image.index(px, py)]) <= kContinuity * footprintP;
}

/// The difference of hits across (x, y) along one image axis: central over two pixels where both
/// sides are continuous with it, else the continuous side; nothing if neither is.
std::optional<glm::dvec3> axisDifference(const HitImage& image, int x, int y, int axis, double footprintXY) {
    const int dx = axis == 0 ? 1 : 0, dy = axis == 1 ? 1 : 0;
    const bool forward = continuous(image, x, y, x + dx, y + dy, footprintXY);
    const bool backward = continuous(image, x, y, x - dx, y - dy, footprintXY);
    const glm::dvec3& h = image.hitMm[image.index(x, y)];
    const glm::dvec3 ahead = forward ? image.hitMm[image.index(x + dx, y + dy)] - h : glm::dvec3(0.0);
    const glm::dvec3 behind = backward ? h - image.hitMm[image.index(x - dx, y - dy)] : glm::dvec3(0.0);
    if (forward && backward) {
        // Central where the two steps are alike; across a depth step (one side twice the other),
        // the shorter side, so the normal of a pixel beside a silhouette is its own surface's.
        const double a = glm::length(ahead), b = glm::length(behind);
        if (a > 2.0 * b) return behind;
        if (b > 2.0 * a) return ahead;
        return ahead + behind;
    }
    if (forward) return ahead;
    if (backward) return h - image.hitMm[image.index(x - dx, y - dy)];
    return std::nullopt;
}

struct Sphere {
    glm::dvec3 centre;
    double radius;
};

/// Least-squares sphere through `points` (|x|^2 = 2 c.x + d, about their mean); nothing for a
/// degenerate (flat or too small) set.
std::optional<Sphere> fitSphere(const std::vector<glm::dvec3>& points) {
    if (points.size() < 10) return std::nullopt;
    glm::dvec3 mean(0.0);
    for (const auto& p : points) mean += p;
    mean /= static_cast<double>(points.size());
    double a[4][5] = {};
    for (const auto& p : points) {
        const glm::dvec3 q = p - mean;
        const double row[4] = {2.0 * q.x, 2.0 * q.y, 2.0 * q.z, 1.0};
        const double rhs = glm::dot(q, q);
        for (int i = 0; i < 4; ++i) {
            for (int j = 0; j < 4; ++j) a[i][j] += row[i] * row[j];
            a[i][4] += row[i] * rhs;
        }
    }
    const double scale = std::max({a[0][0], a[1][1], a[2][2], a[3][3]});
    for (int column = 0; column < 4; ++column) {
        int pivot = column;
        for (int i = column + 1; i < 4; ++i) {
            if (std::abs(a[i][column]) > std::abs(a[pivot][column])) pivot = i;
        }
        if (!(std::abs(a[pivot][column]) > 1e-12 * scale)) return std::nullopt;
        std::swap(a[pivot], a[column]);
        for (int i = 0; i < 4; ++i) {
            if (i == column) continue;
            const double f = a[i][column] / a[column][column];
            for (int j = column; j < 5; ++j) a[i][j] -= f * a[column][j];
        }
    }
    const glm::dvec3 c(a[0][4] / a[0][0], a[1][4] / a[1][1], a[2][4] / a[2][2]);
    const double d = a[3][4] / a[3][3];
    const double r2 = d + glm::dot(c, c);
    if (!(r2 > 0.0) || !std::isfinite(r2)) return std::nullopt;
    return Sphere{c + mean, std::sqrt(r2)};
}

constexpr int kNeighbours[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};

}  // namespace

std::optional<glm::dvec3> hitNormalAt(const HitImage& image, int x, int y) {
    const double l = footprint(image, x, y);
    if (!(l > 0.0)) return std::nullopt;
    const auto right = axisDifference(image, x, y, 0, l);
    const auto down = axisDifference(image, x, y, 1, l);
    if (!right || !down) return std::nullopt;
    const glm::dvec3 n = glm::cross(*down, *right);
    const double length = glm::length(n);
    if (!(length > 0.0)) return std::nullopt;
    return n / length;
}

double surfaceDistanceMm(const HitImage& image, int x0, int y0, int x1, int y1) {
    const glm::dvec3& a = requireHit(image, x0, y0);
    const glm::dvec3& b = requireHit(image, x1, y1);
    return glm::length(a - b);
}

PatchDiameter polypDiameter(const HitImage& image, int x, int y) {
    const glm::dvec3 seed = requireHit(image, x, y);
    const std::size_t pixels = image.hitMm.size();

    // Rules 1 and 2, grown breadth first from the seed. The normals are estimated once, lazily.
    std::vector<uint8_t> normalState(pixels, 0);  // 0 not yet, 1 valid, 2 none
    std::vector<glm::dvec3> normals(pixels);
    auto tangentRule = [&](int qx, int qy) {
        const std::size_t i = image.index(qx, qy);
        if (normalState[i] == 0) {
            const auto n = hitNormalAt(image, qx, qy);
            normalState[i] = n ? 1 : 2;
            if (n) normals[i] = *n;
        }
        if (normalState[i] != 1) return false;
        const glm::dvec3 offset = image.hitMm[i] - seed;
        return glm::dot(normals[i], offset) >= -kTangentSlack * glm::length(offset);
    };
    std::vector<uint8_t> inPatch(pixels, 0);
    {
        std::deque<std::array<int, 2>> queue{{x, y}};
        inPatch[image.index(x, y)] = 1;
        while (!queue.empty()) {
            const auto [px, py] = queue.front();
            queue.pop_front();
            const double l = footprint(image, px, py);
            for (const auto& step : kNeighbours) {
                const int qx = px + step[0], qy = py + step[1];
                if (!image.contains(qx, qy) || inPatch[image.index(qx, qy)] != 0) continue;
                if (!continuous(image, px, py, qx, qy, l) || !tangentRule(qx, qy)) continue;
                inPatch[image.index(qx, qy)] = 1;
                queue.push_back({qx, qy});
            }
        }
    }

    // Rule 3: twice, fit a sphere, drop what lies off it, keep what stays connected to the seed.
    PatchDiameter result;
    result.footprintMm = footprint(image, x, y);
    for (int round = 0; round < kSphereRounds; ++round) {
        std::vector<glm::dvec3> points;
        for (std::size_t i = 0; i < pixels; ++i) {
            if (inPatch[i] != 0) points.push_back(image.hitMm[i]);
        }
        const auto sphere = fitSphere(points);
        glm::dvec3 low(1e300), high(-1e300);
        for (const auto& p : points) low = glm::min(low, p), high = glm::max(high, p);
        // No sphere, or one far larger than the patch: a flat patch, no protrusion to guard.
        if (!sphere || sphere->radius > 20.0 * glm::length(high - low)) break;
        result.sphereCentreMm = sphere->centre;
        result.sphereRadiusMm = sphere->radius;
        const double tolerance = std::max(kSphereTolerance * sphere->radius, 2.0 * result.footprintMm);
        std::vector<uint8_t> kept(pixels, 0);
        std::deque<std::array<int, 2>> queue{{x, y}};
        kept[image.index(x, y)] = 1;
        while (!queue.empty()) {
            const auto [px, py] = queue.front();
            queue.pop_front();
            for (const auto& step : kNeighbours) {
                const int qx = px + step[0], qy = py + step[1];
                if (!image.contains(qx, qy)) continue;
                const std::size_t i = image.index(qx, qy);
                if (inPatch[i] == 0 || kept[i] != 0) continue;
                if (std::abs(glm::length(image.hitMm[i] - sphere->centre) - sphere->radius) > tolerance) continue;
                kept[i] = 1;
                queue.push_back({qx, qy});
            }
        }
        inPatch.swap(kept);
    }

    // The diameter: the farthest pair among the patch's rim pixels.
    std::vector<std::array<int, 2>> rim;
    for (int py = 0; py < image.height; ++py) {
        for (int px = 0; px < image.width; ++px) {
            if (inPatch[image.index(px, py)] == 0) continue;
            ++result.pixelCount;
            bool onRim = false;
            for (const auto& step : kNeighbours) {
                const int qx = px + step[0], qy = py + step[1];
                onRim = onRim || !image.contains(qx, qy) || inPatch[image.index(qx, qy)] == 0;
            }
            if (onRim) rim.push_back({px, py});
        }
    }
    if (result.pixelCount < 3) {
        throw ColonError("the surface patch around pixel " + pixelName(x, y) + " holds " +
                         std::to_string(result.pixelCount) +
                         " pixel(s): no protrusion there (is the pixel on the wall beside a polyp, or the image too coarse?)");
    }
    double best = -1.0;
    for (std::size_t a = 0; a < rim.size(); ++a) {
        const glm::dvec3& pa = image.hitMm[image.index(rim[a][0], rim[a][1])];
        for (std::size_t b = a + 1; b < rim.size(); ++b) {
            const glm::dvec3 d = image.hitMm[image.index(rim[b][0], rim[b][1])] - pa;
            const double distance2 = glm::dot(d, d);
            if (distance2 > best) {
                best = distance2;
                result.end0 = rim[a];
                result.end1 = rim[b];
            }
        }
    }
    result.diameterMm = std::sqrt(best);
    result.end0Mm = image.hitMm[image.index(result.end0[0], result.end0[1])];
    result.end1Mm = image.hitMm[image.index(result.end1[0], result.end1[1])];
    return result;
}

}  // namespace colon
