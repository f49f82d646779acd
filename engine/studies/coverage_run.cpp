#include "engine/studies/coverage_run.h"

#include <chrono>
#include <optional>

namespace engine {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

}  // namespace

CoverageRunSummary runCoverage(Raycaster& raycaster, const CoverageJob& job, colon::SurfaceCoverage& coverage,
                               const CoverageHooks& hooks) {
    validateDisplay(job.display);
    const auto start = Clock::now();
    RenderSettings settings = job.settings;
    settings.isWritingHits = true;
    const int total = static_cast<int>(job.poses.size());
    const auto sceneOf = [&](int index) {
        const CameraPose& pose = job.poses[static_cast<std::size_t>(index)];
        return ScenePose{pose.positionMm, pose.forward, pose.up, job.mmPerMetre};
    };
    const auto submitFrame = [&](int index) {
        std::vector<RenderRequest> requests;
        for (const auto& wall : job.display.walls) {
            const WallView view = wallView(job.display, wall.name, Eye::Centre, sceneOf(index), job.warpMode);
            requests.push_back({view.rays, settings, view.warp});
        }
        return raycaster.submit(requests);
    };

    CoverageRunSummary summary;
    if (hooks.onProgress) hooks.onProgress(0, total);
    std::optional<RenderBatch> inFlight;
    if (total > 0) inFlight.emplace(submitFrame(0));
    for (int index = 0; index < total; ++index) {
        if (hooks.isCancelled && hooks.isCancelled()) throw SequenceCancelled("cancelled");
        std::vector<RenderedImage> images = raycaster.collect(*inFlight);
        inFlight.reset();
        if (index + 1 < total) inFlight.emplace(submitFrame(index + 1));

        const auto measureStart = Clock::now();
        const glm::dvec3 eyeMm =
            wallView(job.display, job.display.walls.front().name, Eye::Centre, sceneOf(index), job.warpMode).rays.eyeMm;
        CoverageFrame frame;
        const std::vector<uint8_t> seenBefore = coverage.seen();
        for (const RenderedImage& image : images) {
            summary.rayCastingMs += std::max(image.deviceMs, 0.0);
            frame.newlySeenMm2 += coverage.addView({image.width, image.height, image.hitMm, eyeMm});
        }
        frame.percentAfter = coverage.percent();
        for (std::size_t e = 0; e < seenBefore.size(); ++e) {
            if (seenBefore[e] == 0 && coverage.seen()[e] != 0) frame.newlySeenElements.push_back(static_cast<uint32_t>(e));
        }
        summary.measureSeconds += secondsSince(measureStart);
        summary.frames.push_back(frame);
        if (hooks.onFrame) {
            std::vector<WallImage> walls;
            for (std::size_t w = 0; w < images.size(); ++w) {
                walls.push_back({Eye::Centre, job.display.walls[w].name, std::move(images[w])});
            }
            hooks.onFrame(index, walls);
        }
        if (hooks.onProgress) hooks.onProgress(index + 1, total);
    }
    summary.seconds = secondsSince(start);
    return summary;
}

}  // namespace engine
