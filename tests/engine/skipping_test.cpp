// Skipping empty space without changing the picture.
// - The tile pass that starts rays past empty space (shaders/ray_start.glsl) against a
//   brute-force march of the whole image: no ray may start beyond its first contributing
//   sample, found without skipping at a tenth of a voxel. Pinhole views of the ball, the tube
//   and the colon phantom and of the shared abdominal CT inside its colon, and the Immersive
//   Cabin's stereo walls bent through the conformal map (chord rays). The images with the pass
//   equal those without.
// - Exact-warped rays, bent at every sample, skip by the map's speed bound: the same hits and
//   images as without skipping, on the cabin's stereo walls at two scales.
// - The tile pass's decision whether the march looks at the distance map: on down a wide tube,
//   where the looks save fetches; off inside the CT's colon, where they find nothing; the image
//   the same either way.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>
#include <string>
#include <utility>

#include <gtest/gtest.h>

#include "conformal/cube_map_baker.h"
#include "conformal/cube_map_speed.h"
#include "engine/display/display.h"
#include "engine/render/raycaster.h"
#include "host_device.h"
#include "tests/support/gpu_scene.h"
#include "tests/support/gpu_test_fixture.h"
#include "tests/support/image_compare.h"
#include "tests/support/pinhole_toward.h"
#include "volumes/analytic_phantom.h"
#include "volumes/colon_phantom.h"
#include "volumes/load_volume.h"

namespace {

using testing_support::cameraToward;
using testing_support::colorDifference;
using Scene = testing_support::GpuScene;

/// What the pass gained over the rays' own starts, for the report and for the test's teeth.
struct StartGain {
    double meanMm = 0.0;        // mean over marching rays of (start after the pass - own start)
    double movedFraction = 0.0; // rays whose start moved by more than a voxel
};

/// Renders `rays` twice with ray parameters in the hit image: by brute force (no skipping, a
/// tenth of a voxel) for the first contributing sample, and with `settings` (skipping and the
/// tile pass) for the starts. Expects every start at or before the first contribution.
StartGain expectStartsBeforeFirstHits(Scene& scene, const engine::ViewRays& rays, engine::RenderSettings settings,
                                      const engine::Warp& warp, const std::string& what) {
    settings.isWritingHits = true;
    settings.isWritingRayStarts = true;
    engine::RenderSettings bruteForce = settings;
    bruteForce.isSkipping = false;
    bruteForce.isAdaptive = false;
    bruteForce.stepVoxels = 0.1;
    const engine::RenderedImage brute = scene.raycaster.render(rays, bruteForce, warp);
    const engine::RenderedImage started = scene.raycaster.render(rays, settings, warp);
    const double voxelMm = std::min({scene.volume.spacingMm.x, scene.volume.spacingMm.y, scene.volume.spacingMm.z});
    // The brute-force hit is refined to a 64th of its 0.1-voxel step; the start is exact.
    const double toleranceMm = 0.01 * voxelMm;
    std::size_t marching = 0, hits = 0, moved = 0, late = 0;
    double gainMm = 0.0;
    for (std::size_t p = 0; p < brute.hitMm.size() / 4; ++p) {
        const float ownStart = started.hitMm[4 * p], start = started.hitMm[4 * p + 1];
        EXPECT_FLOAT_EQ(ownStart, brute.hitMm[4 * p]) << what << ": the same ray, pixel " << p;
        EXPECT_FALSE(start < ownStart) << what << ": a start before the ray's own, pixel " << p;
        EXPECT_TRUE(std::isfinite(start)) << what << ", pixel " << p;
        if (brute.hitMm[4 * p + 3] > 0.5f) {
            ++hits;
            const double firstMm = brute.hitMm[4 * p + 2];
            if (start > firstMm + toleranceMm) {
                if (++late <= 5) {
                    ADD_FAILURE() << what << ": pixel " << p << " starts at " << start << " mm, past its first hit at "
                                  << firstMm << " mm";
                }
            }
        }
        if (start > ownStart || brute.hitMm[4 * p + 3] > 0.5f) {
            ++marching;
            gainMm += start - ownStart;
            moved += start - ownStart > voxelMm ? 1 : 0;
        }
    }
    EXPECT_EQ(late, 0u) << what;
    StartGain gain;
    gain.meanMm = marching ? gainMm / static_cast<double>(marching) : 0.0;
    gain.movedFraction = marching ? static_cast<double>(moved) / static_cast<double>(marching) : 0.0;
    std::cout << what << ": " << hits << " hits; starts moved " << gain.meanMm << " mm on average, "
              << 100.0 * gain.movedFraction << " % of the rays by more than a voxel\n";
    // The pass must leave the image as it was: with a fixed step the march's samples are those of
    // a march from the rays' own starts. (An adaptive step's grid moves with its start, as it
    // does when the march itself skips.)
    if (settings.isAdaptive) return gain;
    settings.isWritingRayStarts = false;
    const engine::RenderedImage withPass = scene.raycaster.render(rays, settings, warp);
    settings.isUsingRayStartPass = false;
    const engine::RenderedImage withoutPass = scene.raycaster.render(rays, settings, warp);
    const auto [worst, mean] = colorDifference(withPass, withoutPass);
    EXPECT_LE(worst, 1) << what;
    EXPECT_LT(mean, 0.01) << what;
    return gain;
}

engine::RenderSettings iso(double isoHu) {
    engine::RenderSettings settings;
    settings.isoHu = isoHu;
    return settings;
}

engine::RenderSettings composite(const std::string& transferFunction) {
    engine::RenderSettings settings;
    settings.mode = engine::RenderMode::Composite;
    settings.transferFunction = transferFunction;
    return settings;
}

/// A 40 mm tube at 0.8 x 0.8 x 0.6 mm, and a view from its axis down its length.
volumes::TubeSpec wideTube() {
    volumes::TubeSpec tube;
    tube.grid.dims = {80, 80, 120};
    tube.grid.spacingMm = glm::dvec3(0.8, 0.8, 0.6);
    tube.axisMm = {31.6, 31.4};
    tube.radiusMm = 20.0;
    return tube;
}

engine::ViewRays downTheTube(const volumes::TubeSpec& tube) {
    const glm::dvec3 eye(tube.axisMm.x, tube.axisMm.y, 5.0);
    auto camera = cameraToward(eye, eye + glm::dvec3(0.1, 0.0, 1.0), 90.0, 160);
    camera.up = {0.0, 1.0, 0.0};
    return engine::viewRaysFrom(camera);
}

/// The shared 3 mm abdominal CT, and the camera of docs/benchmarks/time_against_error.md inside its air-filled colon.
volumes::Volume abdominalCt() {
    return volumes::loadVolume(std::string(CVC_SHARED_DATA_DIR) + "/ct/ts_example_abdomen_3mm.nrrd");
}

engine::ViewRays insideTheCtsColon() {
    return engine::viewRaysFrom(
        cameraToward(glm::dvec3(150.0, 240.0, 231.0), glm::dvec3(124.414, 235.488, 246.0), 90.0, 192));
}

/// The colon phantom at 0.96 mm: its full extent at a sixteenth of the default's voxels.
volumes::ColonPhantom smallColonPhantom() {
    volumes::ColonPhantomSpec spec;
    spec.grid.dims = {160, 160, 160};
    spec.grid.spacingMm = glm::dvec3(0.96);
    return volumes::makeColonPhantom(spec);
}

/// The colon phantom on the device behind a small bake of the Immersive Cabin's map, and a pose
/// on the centreline looking along it.
struct CabinInTheColon {
    CabinInTheColon(const engine::GpuContext& context, std::size_t at)
        : map(bakeSmallMap()), phantom(smallColonPhantom()), colon(context, phantom.volume) {
        colon.raycaster.setCubeMap(map.size, map.rgba);
        pose.positionMm = phantom.centrelineMm.at(at);
        pose.forward = glm::normalize(phantom.centrelineMm.at(at + 4) - phantom.centrelineMm[at]);
        pose.up = std::abs(pose.forward.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(0, 1, 0);
    }
    static conformal::CubeMap bakeSmallMap() {
        conformal::BakeSettings bake;
        bake.size = 128;
        bake.mesh.resolution = 32;
        bake.kind = conformal::MapKind::Conformal;
        return conformal::bakeCubeMap(bake);
    }

    conformal::CubeMap map;
    volumes::ColonPhantom phantom;
    Scene colon;
    engine::ScenePose pose;
};

std::string eyeAndWall(engine::Eye eye, engine::WallName wall) {
    return std::string(eye == engine::Eye::Left ? "left" : "right") + " eye, " + engine::wallNameText(wall) + " wall";
}

class RayStart : public testing_support::GpuTest {};

TEST_F(RayStart, NeverPastTheFirstHitOnTheBallAndInsideTheTube) {
    volumes::BallSpec ball;
    ball.grid.dims = {96, 96, 96};
    ball.centreMm = glm::dvec3(47.5, 47.3, 47.9);
    ball.radiusMm = 30.0;
    Scene ballScene(context(), volumes::makeBallPhantom(ball));
    // From outside: the empty space between the box and the ball is skipped.
    const auto outside = engine::viewRaysFrom(cameraToward(ball.centreMm + glm::dvec3(70, -90, 30), ball.centreMm, 50.0, 160));
    for (int cell : {1, 2, 8}) {
        auto settings = iso(0.0);
        settings.skipCellVoxels = cell;
        const StartGain gain = expectStartsBeforeFirstHits(ballScene, outside, settings, {}, "ball, iso, cell " + std::to_string(cell));
        if (cell == 2) {
            EXPECT_GT(gain.movedFraction, 0.5) << "the pass should move most rays that enter the box";
        }
    }
    auto bone = composite("bone");
    expectStartsBeforeFirstHits(ballScene, outside, bone, {}, "ball, composite");
    // A coarse, jittered, adaptive march keeps the guarantee too.
    auto coarse = iso(0.0);
    coarse.stepVoxels = 2.5;
    coarse.isJittered = true;
    coarse.jitterSeed = 5;
    coarse.isAdaptive = true;
    expectStartsBeforeFirstHits(ballScene, outside, coarse, {}, "ball, iso, coarse jittered adaptive");

    const volumes::TubeSpec tube = wideTube();
    Scene tubeScene(context(), volumes::makeTubePhantom(tube));
    const StartGain gain = expectStartsBeforeFirstHits(tubeScene, downTheTube(tube),
                                                       iso(0.5 * (tube.lumenHu + tube.wallHu)), {}, "tube, iso");
    EXPECT_GT(gain.meanMm, 5.0) << "inside a 40 mm tube the rays should start well past the eye";
}

TEST_F(RayStart, NeverPastTheFirstHitInTheColonPhantomAndTheAbdominalCt) {
    const volumes::ColonPhantom phantom = smallColonPhantom();
    Scene colon(context(), phantom.volume);
    // A point of the centreline with room around it (about 10 mm to the nearest fold).
    const std::size_t at = 50;
    ASSERT_GT(phantom.centrelineMm.size(), at + 8);
    const glm::dvec3 eye = phantom.centrelineMm[at];
    const glm::dvec3 ahead = phantom.centrelineMm[std::min(at + 8, phantom.centrelineMm.size() - 1)];
    const auto inside = engine::viewRaysFrom(cameraToward(eye, ahead, 90.0, 192));
    const StartGain colonGain = expectStartsBeforeFirstHits(colon, inside, iso(-500.0), {}, "colon phantom, iso");
    EXPECT_GT(colonGain.movedFraction, 0.5);
    expectStartsBeforeFirstHits(colon, inside, composite("colon-wall"), {}, "colon phantom, composite");

    Scene ct(context(), abdominalCt());
    const engine::ViewRays inCt = insideTheCtsColon();
    for (int cell : {1, 2}) {
        auto settings = iso(-500.0);
        settings.skipCellVoxels = cell;
        const StartGain gain =
            expectStartsBeforeFirstHits(ct, inCt, settings, {}, "abdominal CT, iso, cell " + std::to_string(cell));
        // 6 mm cells leave the colon's 20 mm hardly a cell of room; 3 mm ones do.
        if (cell == 1) {
            EXPECT_GT(gain.movedFraction, 0.2);
        }
    }
    expectStartsBeforeFirstHits(ct, inCt, composite("colon-wall"), {}, "abdominal CT, composite");
    // From beside the body the pass crosses the air between it and the box.
    const auto outsideCt = engine::viewRaysFrom(
        cameraToward(glm::dvec3(600.0, 150.0, 170.0), glm::dvec3(180.0, 150.0, 170.0), 40.0, 160));
    const StartGain gain = expectStartsBeforeFirstHits(ct, outsideCt, iso(-500.0), {}, "abdominal CT from outside");
    EXPECT_GT(gain.meanMm, 10.0);
}

/// How the tile pass's decision on the march's looks at the distance map came out on one view.
struct LookDecision {
    double lookingFraction = 0.0;  // rays in tiles whose march looks
    double fetchesPerTile = 0.0;   // volume fetches per ray, the looks decided per tile
    double fetchesEverywhere = 0.0;  // ... the looks kept in every tile
};

/// Renders `rays` with the looks decided per tile and kept everywhere: the same image (a fixed
/// step takes the same samples), and the fetches each took.
LookDecision expectLooksChangeNoPixel(Scene& scene, const engine::ViewRays& rays, engine::RenderSettings settings,
                                      const std::string& what) {
    settings.isWritingHits = true;
    settings.isWritingRayStarts = true;
    const engine::RenderedImage flags = scene.raycaster.render(rays, settings, {});
    settings.isWritingRayStarts = false;
    settings.isCountingFetches = true;
    const engine::RenderedImage perTile = scene.raycaster.render(rays, settings, {});
    settings.isLookingInEveryTile = true;
    const engine::RenderedImage everywhere = scene.raycaster.render(rays, settings, {});
    const auto [worst, mean] = colorDifference(perTile, everywhere);
    EXPECT_EQ(worst, 0) << what;
    const std::size_t pixels = flags.hitMm.size() / 4;
    std::size_t looking = 0;
    double fetchesPerTile = 0.0, fetchesEverywhere = 0.0;
    for (std::size_t p = 0; p < pixels; ++p) {
        const int rayFlags = static_cast<int>(flags.hitMm[4 * p + 3]);
        looking += (rayFlags & static_cast<int>(CVC_RAY_STARTS_LOOKS)) != 0 ? 1 : 0;
        fetchesPerTile += perTile.hitMm[4 * p + 3];
        fetchesEverywhere += everywhere.hitMm[4 * p + 3];
    }
    LookDecision decision;
    decision.lookingFraction = static_cast<double>(looking) / static_cast<double>(pixels);
    decision.fetchesPerTile = fetchesPerTile / static_cast<double>(pixels);
    decision.fetchesEverywhere = fetchesEverywhere / static_cast<double>(pixels);
    std::cout << what << ": the march looks in " << 100.0 * decision.lookingFraction << " % of the rays' tiles; "
              << decision.fetchesPerTile << " fetches per ray, " << decision.fetchesEverywhere
              << " with looks in every tile\n";
    return decision;
}

TEST_F(RayStart, TheMarchLooksAtTheDistanceMapOnlyWhereThereIsRoomToSkip) {
    // Down a 40 mm tube at 0.8 mm the lumen has room to skip past the tiles' starts: the looks
    // stay on where they save fetches, and turning them off per tile costs next to none.
    const volumes::TubeSpec tube = wideTube();
    Scene tubeScene(context(), volumes::makeTubePhantom(tube));
    const LookDecision inTube =
        expectLooksChangeNoPixel(tubeScene, downTheTube(tube), iso(0.5 * (tube.lumenHu + tube.wallHu)), "tube, iso");
    EXPECT_GT(inTube.lookingFraction, 0.1) << "looking down the tube, the looks should stay on around its axis";
    EXPECT_LT(inTube.fetchesPerTile, 1.02 * inTube.fetchesEverywhere);

    // Inside the 3 mm CT's colon, 6 mm cells leave no room to skip past the tiles' starts: the
    // looks are off nearly everywhere, and no fetch is added.
    Scene ct(context(), abdominalCt());
    const engine::ViewRays inCt = insideTheCtsColon();
    for (const auto& [settings, what] : {std::pair{iso(-500.0), std::string("abdominal CT, iso")},
                                         std::pair{composite("colon-wall"), std::string("abdominal CT, composite")}}) {
        const LookDecision inColon = expectLooksChangeNoPixel(ct, inCt, settings, what);
        EXPECT_LT(inColon.lookingFraction, 0.2) << what;
        EXPECT_LT(inColon.fetchesPerTile, 1.02 * inColon.fetchesEverywhere) << what;
    }
}

TEST_F(RayStart, NeverPastTheFirstHitOnTheCabinsBentWalls) {
    CabinInTheColon setting(context(), 150);
    Scene& colon = setting.colon;
    engine::ScenePose& pose = setting.pose;
    engine::Display cabin = engine::displayPreset("ic5");
    for (auto& wall : cabin.walls) wall.width = wall.height = 96;
    pose.mmPerMetre = 4.0;
    for (engine::Eye eye : {engine::Eye::Left, engine::Eye::Right}) {
        for (const auto& wall : cabin.walls) {
            const std::string what = eyeAndWall(eye, wall.name);
            const auto chord = engine::wallView(cabin, wall.name, eye, pose, engine::WarpMode::Chord);
            ASSERT_EQ(chord.warp.mode, engine::WarpMode::Chord);
            StartGain gains[2];
            for (bool isUsingChordTable : {true, false}) {
                auto settings = iso(-500.0);
                settings.isUsingChordTable = isUsingChordTable;
                gains[isUsingChordTable ? 1 : 0] = expectStartsBeforeFirstHits(
                    colon, chord.rays, settings, chord.warp, what + (isUsingChordTable ? ", chord table" : ", chord per ray"));
            }
            // With the table the pass reads each tile's cone bound, made for all of its chords,
            // in place of the chords that meet the box this frame: a looser bound, but one that
            // must still carry the starts most of the way.
            EXPECT_GT(gains[1].meanMm, 0.8 * gains[0].meanMm) << what;
        }
    }
    // Exact rays bend at every sample: the tile pass does not move them.
    const auto exact = engine::wallView(cabin, engine::WallName::Front, engine::Eye::Left, pose, engine::WarpMode::Exact);
    auto settings = iso(-500.0);
    settings.isWritingHits = true;
    settings.isWritingRayStarts = true;
    const engine::RenderedImage image = colon.raycaster.render(exact.rays, settings, exact.warp);
    for (std::size_t p = 0; p < image.hitMm.size() / 4; ++p) ASSERT_EQ(image.hitMm[4 * p], image.hitMm[4 * p + 1]);
}

TEST_F(RayStart, ExactBentRaysSkipWithoutChangingTheImageOrTheHits) {
    CabinInTheColon setting(context(), 50);
    Scene& colon = setting.colon;
    engine::ScenePose& pose = setting.pose;
    const conformal::SpeedBoundMap bounds = conformal::speedBoundMap(setting.map.size, setting.map.rgba);
    {
        // Asked to skip along bent rays without the bounds, the ray caster refuses.
        const auto exact = engine::wallView(engine::displayPreset("ic5"), engine::WallName::Front, engine::Eye::Left,
                                            pose, engine::WarpMode::Exact);
        auto settings = iso(-500.0);
        settings.isSkippingBentRays = true;
        EXPECT_THROW(colon.raycaster.render(exact.rays, settings, exact.warp), std::logic_error);
    }
    colon.raycaster.setSpeedBounds(bounds.size, bounds.rgba);
    std::size_t slow = 0;
    for (std::size_t k = 0; k < bounds.rgba.size(); k += 4) slow += bounds.rgba[k] < 3.0f ? 1 : 0;
    std::cout << "the map's speed bound: at most " << bounds.largest << ", under 3 on "
              << 400.0 * static_cast<double>(slow) / static_cast<double>(bounds.rgba.size()) << " % of the directions\n";

    engine::Display cabin = engine::displayPreset("ic5");
    for (auto& wall : cabin.walls) wall.width = wall.height = 64;
    std::size_t fetchesSkipped = 0, fetchesPlain = 0;
    for (double scale : {4.0, 10.0}) {
        pose.mmPerMetre = scale;
        for (engine::Eye eye : {engine::Eye::Left, engine::Eye::Right}) {
            for (const auto& wall : cabin.walls) {
                const std::string what = eyeAndWall(eye, wall.name) + ", scale " + std::to_string(scale);
                const auto exact = engine::wallView(cabin, wall.name, eye, pose, engine::WarpMode::Exact);
                auto settings = iso(-500.0);
                settings.isWritingHits = true;
                settings.isCountingFetches = true;
                settings.isSkipping = false;
                const auto plain = colon.raycaster.render(exact.rays, settings, exact.warp);
                settings.isSkipping = true;
                settings.isSkippingBentRays = true;
                const auto skipped = colon.raycaster.render(exact.rays, settings, exact.warp);
                const auto [worst, mean] = colorDifference(plain, skipped);
                EXPECT_LE(worst, 1) << what;
                EXPECT_LT(mean, 0.01) << what;
                for (std::size_t p = 0; p < plain.hitMm.size() / 4; ++p) {
                    fetchesPlain += static_cast<std::size_t>(plain.hitMm[4 * p + 3]);
                    fetchesSkipped += static_cast<std::size_t>(skipped.hitMm[4 * p + 3]);
                }
                // Hit positions: the same samples, so the same refined hits.
                settings.isCountingFetches = false;
                const auto plainHits = [&] {
                    auto s = settings;
                    s.isSkipping = false;
                    return colon.raycaster.render(exact.rays, s, exact.warp);
                }();
                const auto skippedHits = colon.raycaster.render(exact.rays, settings, exact.warp);
                double worstMm = 0.0;
                for (std::size_t p = 0; p < plainHits.hitMm.size() / 4; ++p) {
                    ASSERT_EQ(plainHits.hitMm[4 * p + 3], skippedHits.hitMm[4 * p + 3]) << what << ", pixel " << p;
                    if (plainHits.hitMm[4 * p + 3] < 0.5f) continue;
                    const glm::dvec3 a(plainHits.hitMm[4 * p], plainHits.hitMm[4 * p + 1], plainHits.hitMm[4 * p + 2]);
                    const glm::dvec3 b(skippedHits.hitMm[4 * p], skippedHits.hitMm[4 * p + 1], skippedHits.hitMm[4 * p + 2]);
                    worstMm = std::max(worstMm, glm::length(a - b));
                }
                EXPECT_LT(worstMm, 1e-3) << what;
            }
        }
    }
    std::cout << "exact warp: " << fetchesSkipped << " volume fetches with skipping, " << fetchesPlain << " without\n";
    EXPECT_LT(static_cast<double>(fetchesSkipped), 0.95 * static_cast<double>(fetchesPlain))
        << "skipping should save the exact rays' fetches in the lumen";
}

}  // namespace
