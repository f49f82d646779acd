#include "engine/studies/patch_views.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "colon/volume_sampling.h"
#include "engine/render/pinhole_camera.h"
#include "engine/render/view_rays.h"

namespace engine {
namespace {

/// The share of `patch`'s area whose elements some pixel of `image` hits.
double shownShare(const RenderedImage& image, const colon::SurfaceCoverage& coverage,
                  const colon::UnseenPatch& patch, double snapMm) {
    std::vector<uint8_t> isInPatch(coverage.surface().size(), 0), isShown(coverage.surface().size(), 0);
    for (uint32_t e : patch.elements) isInPatch[e] = 1;
    for (std::size_t p = 0; p < image.hitMm.size() / 4; ++p) {
        const float* h = &image.hitMm[4 * p];
        if (!(h[3] > 0.5f)) continue;
        const int e = coverage.nearestElement({h[0], h[1], h[2]}, snapMm);
        if (e >= 0 && isInPatch[static_cast<std::size_t>(e)] != 0) isShown[static_cast<std::size_t>(e)] = 1;
    }
    double shown = 0.0;
    for (uint32_t e : patch.elements) shown += isShown[e] != 0 ? coverage.surface().areaMm2[e] : 0.0;
    return shown / patch.areaMm2;
}

}  // namespace

RenderedImage patchView(Raycaster& raycaster, const CameraPose& pose, const glm::dvec3& lookAtMm,
                        const RenderSettings& settings, int pixels) {
    PinholeCamera camera;
    camera.positionMm = pose.positionMm;
    camera.lookAtMm = lookAtMm;
    camera.up = pose.up;
    camera.verticalFovDeg = 90.0;
    camera.width = camera.height = pixels;
    RenderSettings withHits = settings;
    withHits.isWritingHits = true;
    return raycaster.render(viewRaysFrom(camera), withHits);
}

RgbaImage tintedUnseen(RenderedImage image, const colon::SurfaceCoverage& coverage, double snapMm) {
    for (std::size_t p = 0; p < image.hitMm.size() / 4; ++p) {
        const float* h = &image.hitMm[4 * p];
        if (!(h[3] > 0.5f)) continue;
        const int e = coverage.nearestElement({h[0], h[1], h[2]}, snapMm);
        if (e < 0 || coverage.seen()[static_cast<std::size_t>(e)] != 0) continue;
        uint8_t* px = &image.rgba[4 * p];
        px[0] = static_cast<uint8_t>(std::lround(0.45 * px[0] + 0.55 * 235));
        px[1] = static_cast<uint8_t>(std::lround(0.45 * px[1] + 0.55 * 30));
        px[2] = static_cast<uint8_t>(std::lround(0.45 * px[2] + 0.55 * 30));
    }
    return RgbaImage{image.width, image.height, std::move(image.rgba)};
}

std::vector<PatchView> locatePatches(Raycaster& raycaster, const colon::SurfaceCoverage& coverage,
                                     const std::vector<colon::UnseenPatch>& patches,
                                     const std::vector<CameraPose>& poses, const volumes::Volume& volume,
                                     const RenderSettings& settings, double snapMm, int count) {
    constexpr int kNearestFrames = 6;
    constexpr int kProbePixels = 96;
    constexpr double kInFrontMm[] = {4.0, 8.0, 12.0};
    std::vector<PatchView> results;
    for (const auto& patch : patches) {
        if (static_cast<int>(results.size()) >= count) break;
        std::vector<int> order(poses.size());
        for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
        const auto distanceTo = [&](const glm::dvec3& p, int i) { return glm::length(poses[static_cast<std::size_t>(i)].positionMm - p); };
        std::sort(order.begin(), order.end(), [&](int a, int b) { return distanceTo(patch.centreMm, a) < distanceTo(patch.centreMm, b); });
        // Where to look from, each with the up of the frame it comes from.
        std::vector<std::pair<glm::dvec3, int>> candidates;
        for (int i : order) {
            if (static_cast<int>(candidates.size()) >= kNearestFrames) break;
            const glm::dvec3 p = poses[static_cast<std::size_t>(i)].positionMm;
            // Both directions pass the same places: one candidate per place.
            if (std::none_of(candidates.begin(), candidates.end(), [&](const auto& c) { return glm::length(c.first - p) < 1e-6; })) {
                candidates.emplace_back(p, i);
            }
        }
        if (!order.empty()) {
            for (double d : kInFrontMm) {
                const glm::dvec3 p = patch.centreMm + d * patch.normal;
                if (colon::trilinearHu(volume, p) < settings.isoHu) candidates.emplace_back(p, order.front());
            }
        }
        PatchView best;
        best.patch = patch;
        best.shownPercent = -1.0;
        for (const auto& [position, frameIndex] : candidates) {
            const CameraPose& frame = poses[static_cast<std::size_t>(frameIndex)];
            const glm::dvec3 view = patch.centreMm - position;
            if (!(glm::length(view) > 1e-6)) continue;
            const glm::dvec3 up = std::abs(glm::dot(glm::normalize(view), frame.up)) < 0.95 ? frame.up : frame.forward;
            const CameraPose pose = poseLookingAt(position, patch.centreMm, up);
            const double share = shownShare(patchView(raycaster, pose, patch.centreMm, settings, kProbePixels), coverage,
                                            patch, snapMm);
            if (share > best.shownPercent) {
                best.shownPercent = share;
                best.pose = pose;
            }
        }
        best.nearestFrame = *std::min_element(order.begin(), order.end(), [&](int a, int b) {
            return distanceTo(best.pose.positionMm, a) < distanceTo(best.pose.positionMm, b);
        });
        best.shownPercent = 100.0 * std::max(best.shownPercent, 0.0);
        results.push_back(best);
    }
    return results;
}

}  // namespace engine
