#include "engine/studies/view_samples.h"

#include <cmath>
#include <stdexcept>

namespace engine {

std::vector<colon::ViewSample> viewSamples(const ViewRays& rays, const RenderedImage& image) {
    std::vector<colon::ViewSample> samples;
    appendViewSamples(rays, image, samples);
    return samples;
}

void appendViewSamples(const ViewRays& rays, const RenderedImage& image, std::vector<colon::ViewSample>& samples) {
    if (image.width != rays.width || image.height != rays.height) {
        throw std::invalid_argument("view samples: the image does not fit its rays");
    }
    const std::size_t pixels = static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height);
    if (image.hitMm.size() != 4 * pixels || image.rgba.size() != 4 * pixels) {
        throw std::invalid_argument("view samples: the image has no hit positions");
    }
    // A pixel of area a on the rectangle at distance r, seen at angle t from its normal, covers
    // the solid angle a cos t / r^2.
    const glm::dvec3 normal = wallNormalOf(rays);
    const double pixelArea = glm::length(glm::cross(rays.wallUMm, rays.wallVMm)) / static_cast<double>(pixels);
    const std::size_t first = samples.size();
    samples.resize(first + pixels);
    for (int row = 0; row < image.height; ++row)
        for (int column = 0; column < image.width; ++column) {
            const std::size_t n = static_cast<std::size_t>(row) * static_cast<std::size_t>(image.width) +
                                  static_cast<std::size_t>(column);
            colon::ViewSample& sample = samples[first + n];
            const glm::dvec3 onWall = rays.wallOriginMm + (column + 0.5) / image.width * rays.wallUMm +
                                      (row + 0.5) / image.height * rays.wallVMm;
            const glm::dvec3 toWall = onWall - rays.eyeMm;
            const double distance = glm::length(toWall);
            sample.direction = toWall / distance;
            sample.solidAngleSr = pixelArea * std::abs(glm::dot(normal, sample.direction)) / (distance * distance);
            sample.isHit = image.hitMm[4 * n + 3] > 0.5f;
            sample.hitMm = glm::dvec3(image.hitMm[4 * n], image.hitMm[4 * n + 1], image.hitMm[4 * n + 2]);
            for (std::size_t c = 0; c < 4; ++c) sample.rgba[c] = image.rgba[4 * n + c];
        }
}

}  // namespace engine
