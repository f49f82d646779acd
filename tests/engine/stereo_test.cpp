// Stereo: a small ball straight ahead of the viewer appears on the front wall displaced
// between the eyes by the closed-form disparity e (1 - W / D) (e eye separation, W the wall's
// distance, D the ball's): uncrossed (right image to the right) behind the wall, crossed in
// front of it.
#include <cmath>
#include <iostream>

#include <gtest/gtest.h>

#include "engine/display/display.h"
#include "engine/render/raycaster.h"
#include "engine/render/volume_texture.h"
#include "tests/support/gpu_test_fixture.h"
#include "volumes/analytic_phantom.h"
#include "volumes/brick_minmax.h"

namespace {

/// Column of the silhouette's centroid in an image's hit mask.
double centroidColumn(const engine::RenderedImage& image) {
    double sum = 0.0, count = 0.0;
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            if (image.hitMm[4 * (static_cast<std::size_t>(y) * image.width + x) + 3] > 0.5f) {
                sum += x + 0.5;
                count += 1.0;
            }
        }
    }
    return count > 0.0 ? sum / count : -1.0;
}

/// The same centroid for the analytic ball: pixels whose ray meets the sphere.
double analyticCentroidColumn(const engine::ViewRays& rays, const glm::dvec3& centre, double radius) {
    double sum = 0.0, count = 0.0;
    for (int y = 0; y < rays.height; ++y) {
        for (int x = 0; x < rays.width; ++x) {
            const glm::dvec3 d = engine::rayDirectionOf(rays, x, y);
            const glm::dvec3 toCentre = centre - rays.eyeMm;
            const double along = glm::dot(toCentre, d);
            if (along > 0.0 && glm::dot(toCentre, toCentre) - along * along <= radius * radius) {
                sum += x + 0.5;
                count += 1.0;
            }
        }
    }
    return count > 0.0 ? sum / count : -1.0;
}

class Stereo : public testing_support::GpuTest {};

TEST_F(Stereo, DisparityHasTheClosedFormSignAndSize) {
    engine::Display cave = engine::displayPreset("cave6");
    cave.map = conformal::MapKind::None;
    for (auto& wall : cave.walls) wall.width = wall.height = 512;
    const double mmPerMetre = 20.0;
    const double wallDistanceM = 0.5 * cave.boxSizeM.z;  // the front wall is 1.2 m ahead
    const double pixelsPerMetre = 512.0 / cave.boxSizeM.x;

    for (double ballDistanceM : {2.4, 0.6}) {
        // A 3 mm ball (0.15 m in the CAVE) straight ahead of the head, in an empty volume.
        volumes::BallSpec ball;
        ball.grid.dims = {128, 128, 128};
        ball.grid.spacingMm = glm::dvec3(0.5);
        const glm::dvec3 head(32.0, 32.0, 10.0);
        ball.centreMm = head + glm::dvec3(0.0, 0.0, ballDistanceM * mmPerMetre);
        ball.radiusMm = 1.5;
        ball.edgeWidthMm = 0.5;
        const volumes::Volume volume = volumes::makeBallPhantom(ball);
        const volumes::BrickMinMax bricks = volumes::buildBrickMinMax(volume);
        engine::VolumeTexture texture(context(), volume);
        engine::Raycaster raycaster(context(), volume, texture, bricks);

        engine::ScenePose pose;
        pose.positionMm = head;
        pose.forward = {0.0, 0.0, 1.0};
        pose.up = {0.0, 1.0, 0.0};
        pose.mmPerMetre = mmPerMetre;
        engine::RenderSettings settings;
        settings.isoHu = 0.0;
        settings.stepVoxels = 0.25;
        double column[2];
        for (engine::Eye eye : {engine::Eye::Left, engine::Eye::Right}) {
            const auto view = engine::wallView(cave, engine::WallName::Front, eye, pose, engine::WarpMode::None);
            const int i = eye == engine::Eye::Left ? 0 : 1;
            column[i] = centroidColumn(raycaster.render(view.rays, settings, view.warp));
            // Pixel-exact oracle: the analytic sphere's silhouette through the same rays.
            EXPECT_NEAR(column[i], analyticCentroidColumn(view.rays, ball.centreMm, ball.radiusMm), 0.15);
        }
        ASSERT_GT(column[0], 0.0);
        ASSERT_GT(column[1], 0.0);
        const double measuredPx = column[1] - column[0];
        const double expectedPx = cave.eyeSeparationM * (1.0 - wallDistanceM / ballDistanceM) * pixelsPerMetre;
        std::cout << "ball at " << ballDistanceM << " m: disparity " << measuredPx << " px, closed form " << expectedPx
                  << " px\n";
        EXPECT_NEAR(measuredPx, expectedPx, 0.5);
    }
}

}  // namespace
