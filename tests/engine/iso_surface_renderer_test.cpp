// The iso-surface ray caster against analytic surfaces: a ball seen from outside (silhouette
// radius against the closed-form projection, hit depth against the sphere) and a tube seen
// from inside (every hit on the cylinder).
#include <cmath>
#include <iostream>

#include <gtest/gtest.h>

#include "engine/iso_surface_renderer.h"
#include "engine/pinhole_camera.h"
#include "engine/volume_texture.h"
#include "tests/support/gpu_test_fixture.h"
#include "volumes/analytic_phantom.h"

namespace {

using testing_support::GpuTest;

constexpr double kPi = 3.14159265358979323846;

class IsoSurfaceRendering : public GpuTest {
protected:
    static volumes::BallSpec ballSpec() {
        volumes::BallSpec spec;
        spec.grid.dims = {96, 96, 96};
        spec.grid.spacingMm = glm::dvec3(1.0);
        spec.centreMm = glm::dvec3(47.5, 47.3, 47.9);  // off the voxel lattice on purpose
        spec.radiusMm = 30.0;
        return spec;
    }

    static engine::PinholeCamera cameraAt(const glm::dvec3& position, const glm::dvec3& lookAt, double fovDeg, int size) {
        engine::PinholeCamera camera;
        camera.positionMm = position;
        camera.lookAtMm = lookAt;
        camera.up = {0.0, 0.0, 1.0};
        camera.verticalFovDeg = fovDeg;
        camera.width = camera.height = size;
        return camera;
    }

    static void expectAllFinite(const engine::RenderedImage& image) {
        for (float v : image.hitMm) ASSERT_TRUE(std::isfinite(v));
    }
};

TEST_F(IsoSurfaceRendering, BallSilhouetteMatchesAnalyticProjection) {
    const volumes::BallSpec spec = ballSpec();
    const volumes::Volume volume = volumes::makeBallPhantom(spec);
    engine::VolumeTexture texture(context(), volume);
    engine::IsoSurfaceRenderer renderer(context(), texture);

    const double distance = 120.0;
    const double fovDeg = 40.0;
    const int size = 400;
    const auto camera = cameraAt(spec.centreMm - glm::dvec3(0.0, distance, 0.0), spec.centreMm, fovDeg, size);
    const auto image = renderer.render(camera, {0.0, 0.5, 6});
    expectAllFinite(image);

    // Closed form: the ball subtends asin(R / D); a pinhole maps angle a to tan(a) * f pixels.
    const double focalPx = 0.5 * size / std::tan(glm::radians(fovDeg) * 0.5);
    const double expectedRadiusPx = focalPx * std::tan(std::asin(spec.radiusMm / distance));

    // The silhouette is a circle: its radius from the covered area, and from the centre row.
    std::size_t hits = 0;
    for (std::size_t i = 0; i < image.hitMm.size() / 4; ++i) hits += image.hitMm[4 * i + 3] > 0.5f ? 1 : 0;
    const double areaRadiusPx = std::sqrt(static_cast<double>(hits) / kPi);
    std::cout << "silhouette radius: expected " << expectedRadiusPx << " px, from area " << areaRadiusPx << " px\n";
    EXPECT_NEAR(areaRadiusPx, expectedRadiusPx, 1.0);

    const int row = size / 2;
    int first = -1, last = -1;
    for (int x = 0; x < size; ++x) {
        if (image.hitMm[4 * (static_cast<std::size_t>(row) * size + x) + 3] > 0.5f) {
            if (first < 0) first = x;
            last = x;
        }
    }
    ASSERT_GE(first, 0);
    // The ball's centre projects to (size/2 + offset); compare the half-width of the run.
    EXPECT_NEAR(0.5 * (last - first + 1), expectedRadiusPx, 1.0);
}

TEST_F(IsoSurfaceRendering, BallHitDepthWithinQuarterVoxel) {
    const volumes::BallSpec spec = ballSpec();
    const volumes::Volume volume = volumes::makeBallPhantom(spec);
    engine::VolumeTexture texture(context(), volume);
    engine::IsoSurfaceRenderer renderer(context(), texture);

    // Three viewpoints, one of them close and oblique.
    const glm::dvec3 eyes[] = {spec.centreMm - glm::dvec3(0.0, 120.0, 0.0), spec.centreMm + glm::dvec3(90.0, 40.0, -60.0),
                               spec.centreMm + glm::dvec3(0.0, 0.0, 45.0)};
    for (const glm::dvec3& eye : eyes) {
        auto camera = cameraAt(eye, spec.centreMm, 60.0, 256);
        if (std::abs(glm::normalize(spec.centreMm - eye).z) > 0.9) camera.up = {0.0, 1.0, 0.0};
        const auto image = renderer.render(camera, {0.0, 0.5, 6});
        expectAllFinite(image);
        double worstMm = 0.0;
        std::size_t hits = 0;
        for (std::size_t i = 0; i < image.hitMm.size() / 4; ++i) {
            if (image.hitMm[4 * i + 3] < 0.5f) continue;
            const glm::dvec3 p(image.hitMm[4 * i], image.hitMm[4 * i + 1], image.hitMm[4 * i + 2]);
            worstMm = std::max(worstMm, std::abs(glm::length(p - spec.centreMm) - spec.radiusMm));
            ++hits;
        }
        std::cout << "ball hit depth: worst " << worstMm << " mm over " << hits << " hits\n";
        EXPECT_GT(hits, 1000u);
        EXPECT_LT(worstMm, 0.25 * spec.grid.spacingMm.x) << "eye " << eye.x << "," << eye.y << "," << eye.z;
    }
}

TEST_F(IsoSurfaceRendering, TubeSeenFromInsideHitsTheCylinder) {
    volumes::TubeSpec spec;
    spec.grid.dims = {80, 80, 120};
    spec.grid.spacingMm = glm::dvec3(0.8, 0.8, 0.6);  // anisotropic, like CT
    spec.axisMm = {31.6, 31.4};
    spec.radiusMm = 20.0;
    const volumes::Volume volume = volumes::makeTubePhantom(spec);
    engine::VolumeTexture texture(context(), volume);
    engine::IsoSurfaceRenderer renderer(context(), texture);

    const glm::dvec3 eye(spec.axisMm.x, spec.axisMm.y, 5.0);
    auto camera = cameraAt(eye, eye + glm::dvec3(0.1, 0.0, 1.0), 90.0, 256);
    camera.up = {0.0, 1.0, 0.0};
    const double iso = 0.5 * (spec.lumenHu + spec.wallHu);
    const auto image = renderer.render(camera, {iso, 0.5, 6});
    expectAllFinite(image);
    double worstMm = 0.0;
    std::size_t hits = 0;
    for (std::size_t i = 0; i < image.hitMm.size() / 4; ++i) {
        if (image.hitMm[4 * i + 3] < 0.5f) continue;
        const glm::dvec2 p(image.hitMm[4 * i], image.hitMm[4 * i + 1]);
        worstMm = std::max(worstMm, std::abs(glm::length(p - spec.axisMm) - spec.radiusMm));
        ++hits;
    }
    std::cout << "tube hit radius: worst " << worstMm << " mm over " << hits << " hits\n";
    EXPECT_GT(hits, 256u * 256u / 2u);  // the walls fill most of a 90 degree view down the tube
    EXPECT_LT(worstMm, 0.25 * 0.6);     // a quarter of the smallest voxel side
}

TEST_F(IsoSurfaceRendering, NoNaNForCamerasInsideOutsideAndOnTheBox) {
    const volumes::BallSpec spec = ballSpec();
    const volumes::Volume volume = volumes::makeBallPhantom(spec);
    engine::VolumeTexture texture(context(), volume);
    engine::IsoSurfaceRenderer renderer(context(), texture);
    // Inside the ball, inside the box in air, exactly on a box face, on a box corner, and
    // axis-aligned views whose rays have exactly zero components.
    const glm::dvec3 boxMin(-0.5), boxMax(95.5);
    const std::pair<glm::dvec3, glm::dvec3> views[] = {
        {spec.centreMm, spec.centreMm + glm::dvec3(1, 0, 0)},
        {glm::dvec3(5.0, 5.0, 5.0), spec.centreMm},
        {glm::dvec3(boxMin.x, 47.5, 47.5), glm::dvec3(95.5, 47.5, 47.5)},
        {boxMin, spec.centreMm},
        {glm::dvec3(boxMax.x, boxMax.y, 47.5), glm::dvec3(boxMax.x, boxMax.y, 0.0)},
        {glm::dvec3(47.5, -200.0, 47.5), glm::dvec3(47.5, 0.0, 47.5)},
    };
    for (const auto& [eye, target] : views) {
        auto camera = cameraAt(eye, target, 90.0, 65);  // odd size: an exact centre pixel
        if (std::abs(glm::normalize(target - eye).z) > 0.9) camera.up = {0.0, 1.0, 0.0};
        const auto image = renderer.render(camera, {0.0, 0.5, 6});
        expectAllFinite(image);
    }
}

TEST(PinholeCamera, RejectsDegenerateCameras) {
    engine::PinholeCamera camera;
    camera.lookAtMm = camera.positionMm;
    EXPECT_THROW(engine::cameraBasis(camera), std::invalid_argument);
    camera.lookAtMm = {0, 0, -1};
    camera.up = {0, 0, 1};
    EXPECT_THROW(engine::cameraBasis(camera), std::invalid_argument);
    camera.up = {0, 1, 0};
    camera.verticalFovDeg = 0.0;
    EXPECT_THROW(engine::cameraBasis(camera), std::invalid_argument);
    camera.verticalFovDeg = 45.0;
    camera.width = 0;
    EXPECT_THROW(engine::cameraBasis(camera), std::invalid_argument);
}

TEST(PinholeCamera, CentreRayLooksAtTarget) {
    engine::PinholeCamera camera;
    camera.positionMm = {1, 2, 3};
    camera.lookAtMm = {4, 6, 3};
    camera.up = {0, 0, 1};
    camera.width = camera.height = 101;
    const glm::dvec3 d = engine::rayDirection(camera, 50.0, 50.0);
    EXPECT_NEAR(glm::length(d - glm::dvec3(0.6, 0.8, 0.0)), 0.0, 1e-12);
    // The top-left pixel looks up and to the left of the view.
    const glm::dvec3 corner = engine::rayDirection(camera, 0.0, 0.0);
    EXPECT_GT(corner.z, 0.0);
}

}  // namespace
