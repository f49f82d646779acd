// The ray caster against analytic surfaces (a ball seen from outside, a tube seen from inside):
// silhouettes against the closed-form projection, hit positions against the surface, and the
// features that must not change the picture (skipping, adaptive steps at a tiny step, jitter
// with one seed) or must measurably improve it (refinement of the hit).
#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "engine/render/pinhole_camera.h"
#include "engine/render/raycaster.h"
#include "engine/render/transfer_function.h"
#include "engine/render/view_rays.h"
#include "engine/render/volume_texture.h"
#include "tests/support/gpu_scene.h"
#include "tests/support/gpu_test_fixture.h"
#include "tests/support/image_compare.h"
#include "tests/support/pinhole_toward.h"
#include "volumes/analytic_phantom.h"
#include "volumes/brick_minmax.h"

namespace {

using testing_support::colorDifference;

using testing_support::GpuTest;

constexpr double kPi = 3.14159265358979323846;

using Scene = testing_support::GpuScene;

volumes::BallSpec ballSpec() {
    volumes::BallSpec spec;
    spec.grid.dims = {96, 96, 96};
    spec.grid.spacingMm = glm::dvec3(1.0);
    spec.centreMm = glm::dvec3(47.5, 47.3, 47.9);  // off the voxel lattice on purpose
    spec.radiusMm = 30.0;
    return spec;
}

volumes::TubeSpec tubeSpec() {
    volumes::TubeSpec spec;
    spec.grid.dims = {80, 80, 120};
    spec.grid.spacingMm = glm::dvec3(0.8, 0.8, 0.6);  // anisotropic, like CT
    spec.axisMm = {31.6, 31.4};
    spec.radiusMm = 20.0;
    return spec;
}

using testing_support::cameraToward;

engine::RenderSettings isoSettings(double iso, int refinementSteps = 6) {
    engine::RenderSettings settings;
    settings.isoHu = iso;
    settings.refinementSteps = refinementSteps;
    return settings;
}

void expectAllFinite(const engine::RenderedImage& image) {
    for (float v : image.hitMm) ASSERT_TRUE(std::isfinite(v));
}

std::size_t hitCount(const engine::RenderedImage& image) {
    std::size_t hits = 0;
    for (std::size_t i = 0; i < image.hitMm.size() / 4; ++i) hits += image.hitMm[4 * i + 3] > 0.5f ? 1 : 0;
    return hits;
}

/// Largest |distance(hit) - expected| over all hits, with `distance` the analytic surface's.
template <typename Distance>
double worstSurfaceError(const engine::RenderedImage& image, Distance distance) {
    double worst = 0.0;
    for (std::size_t i = 0; i < image.hitMm.size() / 4; ++i) {
        if (image.hitMm[4 * i + 3] < 0.5f) continue;
        const glm::dvec3 p(image.hitMm[4 * i], image.hitMm[4 * i + 1], image.hitMm[4 * i + 2]);
        worst = std::max(worst, std::abs(distance(p)));
    }
    return worst;
}


class Raycasting : public GpuTest {};

TEST_F(Raycasting, BallSilhouetteMatchesAnalyticProjection) {
    const volumes::BallSpec spec = ballSpec();
    Scene scene(context(), volumes::makeBallPhantom(spec));
    const double distance = 120.0, fovDeg = 40.0;
    const int size = 400;
    const auto camera = cameraToward(spec.centreMm - glm::dvec3(0.0, distance, 0.0), spec.centreMm, fovDeg, size);
    const auto image = scene.raycaster.render(engine::viewRaysFrom(camera), isoSettings(0.0));
    expectAllFinite(image);

    // Closed form: the ball subtends asin(R / D); a pinhole maps angle a to tan(a) * f pixels.
    const double focalPx = 0.5 * size / std::tan(glm::radians(fovDeg) * 0.5);
    const double expectedRadiusPx = focalPx * std::tan(std::asin(spec.radiusMm / distance));
    const double areaRadiusPx = std::sqrt(static_cast<double>(hitCount(image)) / kPi);
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
    EXPECT_NEAR(0.5 * (last - first + 1), expectedRadiusPx, 1.0);
}

TEST_F(Raycasting, BallHitDepthWithinQuarterVoxelAndRefinementHelps) {
    const volumes::BallSpec spec = ballSpec();
    Scene scene(context(), volumes::makeBallPhantom(spec));
    const auto sphereDistance = [&](const glm::dvec3& p) { return glm::length(p - spec.centreMm) - spec.radiusMm; };
    const glm::dvec3 eyes[] = {spec.centreMm - glm::dvec3(0.0, 120.0, 0.0), spec.centreMm + glm::dvec3(90.0, 40.0, -60.0),
                               spec.centreMm + glm::dvec3(0.0, 0.0, 45.0)};
    for (const glm::dvec3& eye : eyes) {
        const auto rays = engine::viewRaysFrom(cameraToward(eye, spec.centreMm, 60.0, 256));
        for (engine::VolumeFilter filter : {engine::VolumeFilter::Trilinear, engine::VolumeFilter::Tricubic}) {
            auto refined = isoSettings(0.0, 6);
            refined.filter = filter;
            auto raw = isoSettings(0.0, 0);
            raw.filter = filter;
            const auto refinedImage = scene.raycaster.render(rays, refined);
            const auto rawImage = scene.raycaster.render(rays, raw);
            expectAllFinite(refinedImage);
            const double refinedMm = worstSurfaceError(refinedImage, sphereDistance);
            const double rawMm = worstSurfaceError(rawImage, sphereDistance);
            std::cout << (filter == engine::VolumeFilter::Tricubic ? "tricubic" : "trilinear")
                      << " ball hit depth: worst " << refinedMm << " mm refined, " << rawMm << " mm unrefined, "
                      << hitCount(refinedImage) << " hits\n";
            EXPECT_GT(hitCount(refinedImage), 1000u);
            EXPECT_LT(refinedMm, 0.25 * spec.grid.spacingMm.x);
            EXPECT_LT(refinedMm * 4.0, rawMm) << "refinement should cut the error by far more than 4x";
        }
    }
}

TEST_F(Raycasting, TubeSeenFromInsideHitsTheCylinder) {
    const volumes::TubeSpec spec = tubeSpec();
    Scene scene(context(), volumes::makeTubePhantom(spec));
    const glm::dvec3 eye(spec.axisMm.x, spec.axisMm.y, 5.0);
    auto camera = cameraToward(eye, eye + glm::dvec3(0.1, 0.0, 1.0), 90.0, 256);
    camera.up = {0.0, 1.0, 0.0};
    const auto image = scene.raycaster.render(engine::viewRaysFrom(camera), isoSettings(0.5 * (spec.lumenHu + spec.wallHu)));
    expectAllFinite(image);
    const double worstMm = worstSurfaceError(
        image, [&](const glm::dvec3& p) { return glm::length(glm::dvec2(p) - spec.axisMm) - spec.radiusMm; });
    std::cout << "tube hit radius: worst " << worstMm << " mm over " << hitCount(image) << " hits\n";
    EXPECT_GT(hitCount(image), 256u * 256u / 2u);  // the walls fill most of a 90 degree view down the tube
    EXPECT_LT(worstMm, 0.25 * 0.6);                // a quarter of the smallest voxel side
}

TEST_F(Raycasting, SkippingLeavesTheImageUnchanged) {
    const volumes::BallSpec ball = ballSpec();
    Scene scene(context(), volumes::makeBallPhantom(ball));
    const auto rays = engine::viewRaysFrom(cameraToward(ball.centreMm + glm::dvec3(70, -90, 30), ball.centreMm, 50.0, 200));
    for (engine::RenderMode mode : {engine::RenderMode::IsoSurface, engine::RenderMode::Composite}) {
        for (bool isJittered : {false, true}) {
            engine::RenderSettings settings = isoSettings(0.0);
            settings.mode = mode;
            settings.transferFunction = "bone";
            settings.isJittered = isJittered;
            settings.jitterSeed = 17;
            // A step longer than the ball's 2 mm edge ramp: samples can land past the thin
            // layer of cells that straddle the iso value, inside the ball, and must stop there
            // with skipping as without.
            settings.stepVoxels = isJittered ? 2.5 : 0.5;
            settings.isSkipping = false;
            const auto plain = scene.raycaster.render(rays, settings);
            // Fine cells, the 8^3 bricks, and single voxels; with and without the tile pass that
            // starts the rays past empty space.
            for (int cell : {2, 8, 1}) {
                for (bool isStartPass : {true, false}) {
                    settings.isSkipping = true;
                    settings.skipCellVoxels = cell;
                    settings.isUsingRayStartPass = isStartPass;
                    const auto skipped = scene.raycaster.render(rays, settings);
                    const auto [worst, mean] = colorDifference(plain, skipped);
                    EXPECT_LE(worst, 1) << "mode " << static_cast<int>(mode) << " jitter " << isJittered << " cell "
                                        << cell << " start pass " << isStartPass;
                    EXPECT_LT(mean, 0.01);
                    EXPECT_EQ(hitCount(plain), hitCount(skipped));
                }
            }
        }
    }
}

TEST_F(Raycasting, AdaptiveStepAgreesAtATinyStep) {
    const volumes::TubeSpec spec = tubeSpec();
    Scene scene(context(), volumes::makeTubePhantom(spec));
    const glm::dvec3 eye(spec.axisMm.x, spec.axisMm.y, 3.0);
    auto camera = cameraToward(eye, eye + glm::dvec3(0.0, 0.0, 1.0), 80.0, 160);
    const auto rays = engine::viewRaysFrom(camera);
    engine::RenderSettings settings = isoSettings(0.5 * (spec.lumenHu + spec.wallHu));
    settings.stepVoxels = 0.05;
    settings.minStepVoxels = 0.05;
    settings.maxStepVoxels = 0.05;  // adaptive may not exceed the tiny step: results must agree
    const auto fixed = scene.raycaster.render(rays, settings);
    settings.isAdaptive = true;
    const auto adaptive = scene.raycaster.render(rays, settings);
    const auto [worst, mean] = colorDifference(fixed, adaptive);
    EXPECT_LE(worst, 2);
    EXPECT_LT(mean, 0.05);

    // With room to grow, the adaptive step still finds the same wall (within half a voxel).
    settings.stepVoxels = 0.25;
    settings.minStepVoxels = 0.25;
    settings.maxStepVoxels = 2.0;
    const auto grown = scene.raycaster.render(rays, settings);
    const double worstMm = worstSurfaceError(
        grown, [&](const glm::dvec3& p) { return glm::length(glm::dvec2(p) - spec.axisMm) - spec.radiusMm; });
    EXPECT_LT(worstMm, 0.3);
}

TEST_F(Raycasting, JitterIsReproducibleBySeed) {
    const volumes::BallSpec spec = ballSpec();
    Scene scene(context(), volumes::makeBallPhantom(spec));
    const auto rays = engine::viewRaysFrom(cameraToward(spec.centreMm - glm::dvec3(0, 100, 0), spec.centreMm, 50.0, 128));
    engine::RenderSettings settings;
    settings.mode = engine::RenderMode::Composite;
    settings.transferFunction = "bone";
    settings.stepVoxels = 1.5;  // coarse, so jitter visibly changes the samples
    settings.isJittered = true;
    settings.jitterSeed = 1;
    const auto first = scene.raycaster.render(rays, settings);
    const auto again = scene.raycaster.render(rays, settings);
    EXPECT_EQ(first.rgba, again.rgba);
    settings.jitterSeed = 2;
    const auto other = scene.raycaster.render(rays, settings);
    EXPECT_GT(colorDifference(first, other).second, 0.01);
}

TEST_F(Raycasting, CompositeOpacityFrontFindsTheBall) {
    // The "bone" preset is opaque well below the ball's 1000 HU: the 50 % opacity front sits
    // within a voxel of where the ramp crosses the preset's opaque range.
    const volumes::BallSpec spec = ballSpec();
    Scene scene(context(), volumes::makeBallPhantom(spec));
    const auto rays = engine::viewRaysFrom(cameraToward(spec.centreMm - glm::dvec3(0, 110, 0), spec.centreMm, 50.0, 160));
    engine::RenderSettings settings;
    settings.mode = engine::RenderMode::Composite;
    settings.transferFunction = "bone";
    settings.stepVoxels = 0.25;
    const auto image = scene.raycaster.render(rays, settings);
    expectAllFinite(image);
    const double worstMm = worstSurfaceError(
        image, [&](const glm::dvec3& p) { return glm::length(p - spec.centreMm) - spec.radiusMm; });
    EXPECT_GT(hitCount(image), 1000u);
    EXPECT_LT(worstMm, 1.0);
}

TEST_F(Raycasting, TableCorrectedOpacityEqualsThePerSampleCorrection) {
    // A fixed step samples a table whose opacities the host corrected for that step; the
    // adaptive step corrects each sample in the shader. Held to one step, the two must agree,
    // at steps far from the reference 1 mm (where the correction matters) and at it.
    const volumes::BallSpec spec = ballSpec();
    Scene scene(context(), volumes::makeBallPhantom(spec));
    const auto rays = engine::viewRaysFrom(cameraToward(spec.centreMm - glm::dvec3(0, 110, 0), spec.centreMm, 50.0, 160));
    for (const std::string transfer : {"soft-tissue", "bone"}) {
        for (double stepVoxels : {0.2, 1.0, 2.5}) {
            engine::RenderSettings settings;
            settings.mode = engine::RenderMode::Composite;
            settings.transferFunction = transfer;
            settings.stepVoxels = stepVoxels;
            settings.isSkipping = false;  // the adaptive step's skips and start leave the fixed grid
            const auto tableCorrected = scene.raycaster.render(rays, settings);
            settings.isAdaptive = true;
            settings.minStepVoxels = settings.maxStepVoxels = stepVoxels;
            const auto sampleCorrected = scene.raycaster.render(rays, settings);
            const auto [worst, mean] = colorDifference(tableCorrected, sampleCorrected);
            EXPECT_LE(worst, 2) << transfer << " at " << stepVoxels << " voxels";
            EXPECT_LT(mean, 0.05) << transfer << " at " << stepVoxels << " voxels";
            EXPECT_EQ(hitCount(tableCorrected), hitCount(sampleCorrected)) << transfer << " at " << stepVoxels;
        }
        // Without any correction the soft-tissue look would change visibly with the step: the
        // comparison above has teeth.
    }
}

TEST(TransferTable, CorrectionForAStepComposesAsMaterialDoes) {
    const engine::TransferTable table = engine::tabulate(engine::transferFunctionPreset("soft-tissue"));
    const engine::TransferTable same = engine::correctedForStep(table, engine::kTransferReferenceStepMm);
    const engine::TransferTable half = engine::correctedForStep(table, 0.5 * engine::kTransferReferenceStepMm);
    const engine::TransferTable triple = engine::correctedForStep(table, 3.0 * engine::kTransferReferenceStepMm);
    for (std::size_t e = 0; e < table.rgba.size(); ++e) {
        const double a = table.rgba[e].a;
        EXPECT_NEAR(same.rgba[e].a, a, 1e-6);
        // Two half steps let through what one whole step does: (1 - a_half)^2 = 1 - a.
        EXPECT_NEAR((1.0 - half.rgba[e].a) * (1.0 - half.rgba[e].a), 1.0 - a, 1e-6);
        EXPECT_NEAR(1.0 - triple.rgba[e].a, std::pow(1.0 - a, 3.0), 1e-6);
        EXPECT_EQ(half.rgba[e].a > 0.0f, a > 0.0) << "skipping must select the same bricks";
        EXPECT_EQ(glm::vec3(half.rgba[e]), glm::vec3(table.rgba[e])) << "colours stay";
    }
    EXPECT_THROW(engine::correctedForStep(table, 0.0), std::invalid_argument);
    EXPECT_THROW(engine::correctedForStep(table, std::nan("")), std::invalid_argument);
}

/// The opacity the shader reads at `hu`: the table sampled with linear filtering, clamped to its
/// end entries (transfer_function.glsl), evaluated here in double precision.
double filteredOpacity(const engine::TransferTable& table, double hu) {
    const auto n = static_cast<long long>(table.rgba.size());
    const double index = (hu - table.firstHu) * static_cast<double>(n - 1) / (table.lastHu - table.firstHu);
    const double below = std::floor(index);
    const double f = index - below;
    const auto at = [&](double e) {
        return static_cast<double>(table.rgba[static_cast<std::size_t>(std::clamp(static_cast<long long>(e), 0LL, n - 1))].a);
    };
    return (1.0 - f) * at(below) + f * at(below + 1.0);
}

// The march skips the table's fetch outside the visible range, so every value the filtered
// table gives an opacity must lie inside it. The range must also be tight: each finite end lies
// within three entries of a value that is visible (an always-open range would pass the first
// check and save nothing).
TEST(TransferTable, VisibleRangeHoldsEveryValueWithOpacity) {
    std::vector<std::pair<std::string, engine::TransferTable>> tables;
    for (const std::string& name : engine::transferFunctionPresetNames()) {
        tables.emplace_back(name, engine::tabulate(engine::transferFunctionPreset(name)));
    }
    const glm::vec3 grey(0.5f);
    const auto spike = [&](int entry, int entries) {
        engine::TransferTable table = engine::tabulate({"dark", {{-1000.0, grey, 0.0f}, {1000.0, grey, 0.0f}}}, entries);
        table.rgba[static_cast<std::size_t>(entry)].a = 0.25f;
        return table;
    };
    tables.emplace_back("one visible entry in the middle", spike(37, 101));
    tables.emplace_back("the first entry visible", spike(0, 101));
    tables.emplace_back("the second entry visible", spike(1, 101));
    tables.emplace_back("the last entry visible", spike(100, 101));
    tables.emplace_back("two entries", spike(1, 2));
    for (const auto& [what, table] : tables) {
        const engine::VisibleHuRange range = engine::visibleHuRangeOf(table);
        const double binHu = (table.lastHu - table.firstHu) / static_cast<double>(table.rgba.size() - 1);
        const double from = table.firstHu - 20.0 * binHu, to = table.lastHu + 20.0 * binHu;
        double firstVisible = std::numeric_limits<double>::infinity(), lastVisible = -firstVisible;
        for (double hu = from; hu <= to; hu += binHu / 64.0) {
            if (filteredOpacity(table, hu) <= 0.0) continue;
            firstVisible = std::min(firstVisible, hu);
            lastVisible = std::max(lastVisible, hu);
            EXPECT_TRUE(range.fromHu < hu && hu < range.toHu)
                << what << ": " << hu << " HU has opacity outside (" << range.fromHu << ", " << range.toHu << ")";
        }
        ASSERT_LE(firstVisible, lastVisible) << what << ": the sweep found nothing visible";
        const double unbounded = std::numeric_limits<float>::max();
        // Unbounded only where the table's end is visible or next to it.
        if (range.fromHu > -unbounded) {
            EXPECT_LT(firstVisible - range.fromHu, 3.0 * binHu) << what;
        } else {
            EXPECT_LT(firstVisible, table.firstHu + 3.0 * binHu) << what;
        }
        if (range.toHu < unbounded) {
            EXPECT_LT(range.toHu - lastVisible, 3.0 * binHu) << what;
        } else {
            EXPECT_GT(lastVisible, table.lastHu - 3.0 * binHu) << what;
        }
    }
    const engine::TransferTable clear = engine::tabulate({"clear", {{-1000.0, grey, 0.0f}, {1000.0, grey, 0.0f}}});
    const engine::VisibleHuRange none = engine::visibleHuRangeOf(clear);
    EXPECT_GT(none.fromHu, none.toHu) << "nothing is visible: no value may pass";
}

TEST_F(Raycasting, NoNaNForCamerasInsideOutsideAndOnTheBox) {
    const volumes::BallSpec spec = ballSpec();
    Scene scene(context(), volumes::makeBallPhantom(spec));
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
        const auto rays = engine::viewRaysFrom(cameraToward(eye, target, 90.0, 65));  // odd size: an exact centre pixel
        for (engine::RenderMode mode : {engine::RenderMode::IsoSurface, engine::RenderMode::Composite}) {
            engine::RenderSettings settings = isoSettings(0.0);
            settings.mode = mode;
            settings.transferFunction = "bone";
            settings.filter = engine::VolumeFilter::Tricubic;
            settings.isAdaptive = true;
            settings.isJittered = true;
            expectAllFinite(scene.raycaster.render(rays, settings));
        }
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

TEST(PinholeCamera, ViewRaysMatchTheCameraModel) {
    engine::PinholeCamera camera;
    camera.positionMm = {1, 2, 3};
    camera.lookAtMm = {4, 6, 3};
    camera.up = {0, 0, 1};
    camera.width = 101;
    camera.height = 75;
    const auto rays = engine::viewRaysFrom(camera);
    const glm::dvec3 centre = engine::rayDirectionOf(rays, 50.0, 37.0);
    EXPECT_NEAR(glm::length(centre - glm::dvec3(0.6, 0.8, 0.0)), 0.0, 1e-12);
    for (double column : {0.0, 13.0, 100.0}) {
        for (double row : {0.0, 40.0, 74.0}) {
            EXPECT_NEAR(glm::length(engine::rayDirectionOf(rays, column, row) - engine::rayDirection(camera, column, row)),
                        0.0, 1e-12);
        }
    }
    EXPECT_GT(engine::rayDirectionOf(rays, 0.0, 0.0).z, 0.0);  // the top-left pixel looks up
    EXPECT_NEAR(glm::length(engine::wallNormalOf(rays) - glm::dvec3(0.6, 0.8, 0.0)), 0.0, 1e-12);
}

}  // namespace
