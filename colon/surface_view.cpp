#include "colon/surface_view.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "colon/colon_error.h"
#include "colon/surface_measure.h"
#include "colon/volume_sampling.h"

namespace colon {
namespace {

bool isFinite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

/// The first crossing of the iso value along the ray, bisected between the last sample below it
/// and the first at or above it; nothing within `maxDistanceMm` or outside the volume's box.
bool firstHit(const volumes::Volume& volume, const glm::dvec3& origin, const glm::dvec3& direction, double isoHu,
              double stepMm, double maxDistanceMm, glm::dvec3& hit) {
    const glm::dvec3 extent = glm::dvec3(volume.dims[0] - 1, volume.dims[1] - 1, volume.dims[2] - 1) * volume.spacingMm;
    const auto steps = static_cast<long>(std::ceil(maxDistanceMm / stepMm));
    double before = 0.0;
    for (long n = 1; n <= steps; ++n) {
        const double t = static_cast<double>(n) * stepMm;
        const glm::dvec3 p = origin + t * direction;
        if (glm::any(glm::lessThan(p, glm::dvec3(0.0))) || glm::any(glm::greaterThan(p, extent))) return false;
        if (trilinearHu(volume, p) < isoHu) {
            before = t;
            continue;
        }
        double lo = before, hi = t;
        for (int round = 0; round < 20; ++round) {
            const double mid = 0.5 * (lo + hi);
            (trilinearHu(volume, origin + mid * direction) < isoHu ? lo : hi) = mid;
        }
        hit = origin + 0.5 * (lo + hi) * direction;
        return true;
    }
    return false;
}

}  // namespace

HitImage surfaceView(const volumes::Volume& volume, const SurfaceViewRequest& request) {
    if (request.size < 8 || request.size > 1024) {
        throw ColonError("a surface view must be 8 to 1024 pixels a side, not " + std::to_string(request.size));
    }
    if (!(request.fovDeg > 0.0 && request.fovDeg < 170.0) || !(request.maxDistanceMm > 0.0) ||
        !isFinite(request.eyeMm) || !isFinite(request.lookAtMm) || !isFinite(request.up)) {
        throw ColonError("a surface view needs a finite eye, look-at point and up, and a field of view in (0, 170) degrees");
    }
    const glm::dvec3 toward = request.lookAtMm - request.eyeMm;
    const glm::dvec3 across = glm::cross(toward, request.up);
    if (!(glm::length(toward) > 0.0) || !(glm::length(across) > 1e-9 * glm::length(toward) * glm::length(request.up))) {
        throw ColonError("a surface view's eye and look-at point coincide, or its up is parallel to the view");
    }
    if (trilinearHu(volume, request.eyeMm) >= request.isoHu) {
        throw ColonError("a surface view's eye lies in tissue (at or above the iso value)");
    }
    const glm::dvec3 forward = glm::normalize(toward);
    const glm::dvec3 right = glm::normalize(across);
    const glm::dvec3 up = glm::cross(right, forward);
    const double halfWidth = std::tan(0.5 * request.fovDeg * M_PI / 180.0);
    const double stepMm = 0.25 * std::min({volume.spacingMm.x, volume.spacingMm.y, volume.spacingMm.z});

    HitImage image;
    image.width = image.height = request.size;
    image.hitMm.assign(static_cast<std::size_t>(request.size) * static_cast<std::size_t>(request.size), glm::dvec3(0.0));
    image.isHit.assign(image.hitMm.size(), 0);
    for (int y = 0; y < request.size; ++y) {
        const double v = halfWidth * (1.0 - 2.0 * (y + 0.5) / request.size);
        for (int x = 0; x < request.size; ++x) {
            const double u = halfWidth * (2.0 * (x + 0.5) / request.size - 1.0);
            const glm::dvec3 direction = glm::normalize(forward + u * right + v * up);
            glm::dvec3 hit;
            if (firstHit(volume, request.eyeMm, direction, request.isoHu, stepMm, request.maxDistanceMm, hit)) {
                image.hitMm[image.index(x, y)] = hit;
                image.isHit[image.index(x, y)] = 1;
            }
        }
    }
    return image;
}

std::vector<uint8_t> shadedSurfaceView(const HitImage& image, const glm::dvec3& eyeMm) {
    std::vector<uint8_t> rgba(static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) * 4, 0);
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            const std::size_t n = image.index(x, y);
            rgba[4 * n + 3] = 255;
            if (!image.isHit[n]) continue;
            const glm::dvec3 toEye = glm::normalize(eyeMm - image.hitMm[n]);
            const auto normal = hitNormalAt(image, x, y);
            const double lambert = normal ? std::max(0.0, glm::dot(*normal, toEye)) : 0.5;
            const auto grey = static_cast<uint8_t>(std::lround(40.0 + 215.0 * lambert));
            rgba[4 * n] = rgba[4 * n + 1] = rgba[4 * n + 2] = grey;
        }
    }
    return rgba;
}

}  // namespace colon
