// Coverage along fly-throughs rendered on the device, on synthetic colons whose answers are
// known: a plain tube seen by every wall, a pocket no point of the axis can look into, folds
// that hide the top of each bay from everything but the ceiling, and the order of frames.
#include <algorithm>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "colon/surface_coverage.h"
#include "colon/wall_surface.h"
#include "conformal/cube_map_baker.h"
#include "engine/display/display_map.h"
#include "engine/studies/coverage_run.h"
#include "tests/support/gpu_scene.h"
#include "tests/support/gpu_test_fixture.h"
#include "tests/support/tube_volume.h"

namespace {

using testing_support::TubeSpec;

/// A preset with every wall's pixels divided by `reduction` (same density on every wall).
engine::Display smallDisplay(const std::string& name, conformal::MapKind map, int reduction) {
    engine::Display display = engine::displayPreset(name);
    display.map = map;
    for (auto& wall : display.walls) {
        wall.width = std::max(1, wall.width / reduction);
        wall.height = std::max(1, wall.height / reduction);
    }
    return display;
}

/// Poses on the tube's axis from z0 to z1, looking along +z with +y up.
std::vector<engine::CameraPose> axisPoses(const TubeSpec& spec, double z0, double z1, double step) {
    std::vector<engine::CameraPose> poses;
    for (double z = z0; z <= z1 + 1e-9; z += step) {
        poses.push_back({{0.5 * spec.extentMm.x, 0.5 * spec.extentMm.y, z}, {0, 0, 1}, {0, 1, 0}});
    }
    return poses;
}

class CoverageRun : public testing_support::GpuTest {
protected:
    /// Coverage of `display` over `poses` in the tube `spec`.
    std::unique_ptr<colon::SurfaceCoverage> cover(testing_support::GpuScene& scene, const colon::WallSurface& wall,
                                                  const engine::Display& display,
                                                  const std::vector<engine::CameraPose>& poses) {
        if (display.map != conformal::MapKind::None) {
            const conformal::CubeMap map = engine::cubeMapFor(display, 256, "");
            scene.raycaster.setCubeMap(map.size, map.rgba);
        }
        engine::CoverageJob job;
        job.display = display;
        job.poses = poses;
        job.mmPerMetre = 4.0;
        auto coverage = std::make_unique<colon::SurfaceCoverage>(wall, colon::CoverageSettings{});
        const engine::CoverageRunSummary summary = engine::runCoverage(scene.raycaster, job, *coverage);
        EXPECT_EQ(summary.frames.size(), poses.size());
        for (const auto& frame : summary.frames) EXPECT_LE(frame.percentAfter, 100.0);
        return coverage;
    }
};

TEST_F(CoverageRun, Ic6FromTheAxisSeesAPlainTubeWhole) {
    const TubeSpec spec;
    testing_support::GpuScene scene(context(), testing_support::tubeVolume(spec));
    const colon::WallSurface wall = colon::colonWallSurface(scene.volume, testing_support::airMask(scene.volume));
    const auto coverage = cover(scene, wall, smallDisplay("ic6", conformal::MapKind::None, 10),
                                axisPoses(spec, spec.zStartMm + 4.0, spec.zEndMm - 4.0, 2.0));
    EXPECT_GT(coverage->percent(), 98.0);
    EXPECT_LE(coverage->percent(), 100.0);
}

TEST_F(CoverageRun, APocketNoViewReachesIsReportedUnseenWithItsArea) {
    TubeSpec spec;
    spec.hasPocket = true;
    spec.extentMm.x += 12.0;
    testing_support::GpuScene scene(context(), testing_support::tubeVolume(spec));
    const colon::WallSurface wall = colon::colonWallSurface(scene.volume, testing_support::airMask(scene.volume));
    const auto coverage = cover(scene, wall, smallDisplay("ic6", conformal::MapKind::None, 10),
                                axisPoses(spec, spec.zStartMm + 4.0, spec.zEndMm - 4.0, 2.0));
    // The chamber is what no point of the axis sees, but for a spot of its far wall straight
    // through the neck (under 3 mm square). Its area is taken from the mesh, so that this test
    // is of what was seen; the mesh's area is held to closed forms by the wall-surface tests.
    const testing_support::PocketBoxes b = testing_support::pocketBoxes(spec);
    double hidden = 0.0;
    for (std::size_t e = 0; e < wall.size(); ++e) {
        if (testing_support::boxDistance(wall.centreMm[e], b.chamberCentre, b.chamberHalf + 0.3) < 0.0) hidden += wall.areaMm2[e];
    }
    EXPECT_GT(hidden, 150.0);
    const auto patches = coverage->unseenPatches(10.0);
    ASSERT_FALSE(patches.empty());
    const colon::UnseenPatch& largest = patches.front();
    EXPECT_LT(testing_support::boxDistance(largest.centreMm, b.chamberCentre, b.chamberHalf + 1.0), 0.0)
        << "the largest unseen patch lies in the pocket";
    EXPECT_NEAR(largest.areaMm2, hidden, 0.10 * hidden);
    // Everything else was seen: the pocket is the one hidden place.
    EXPECT_LT(coverage->wallAreaMm2() - coverage->seenAreaMm2() - largest.areaMm2, 0.01 * coverage->wallAreaMm2());
}

TEST_F(CoverageRun, FramesInAnyOrderSeeTheSameWall) {
    TubeSpec spec;
    spec.foldSpacingMm = 10.0;
    spec.foldFirstMm = 20.0;
    spec.foldLastMm = 60.0;
    testing_support::GpuScene scene(context(), testing_support::tubeVolume(spec));
    const colon::WallSurface wall = colon::colonWallSurface(scene.volume, testing_support::airMask(scene.volume));
    const engine::Display display = smallDisplay("ic5", conformal::MapKind::None, 14);
    std::vector<engine::CameraPose> poses = axisPoses(spec, 14.0, 66.0, 4.0);
    const auto inOrder = cover(scene, wall, display, poses);
    std::shuffle(poses.begin(), poses.end(), std::mt19937(3));
    const auto shuffled = cover(scene, wall, display, poses);
    EXPECT_EQ(inOrder->seen(), shuffled->seen());
    EXPECT_EQ(inOrder->percent(), shuffled->percent());
}

TEST_F(CoverageRun, WithoutTheMapIc5MissesWhatOnlyTheCeilingShows) {
    // Folds 8 mm apart, 4 mm high in a tube of 8 mm radius: the top of each bay is seen from
    // inside the bay within 53 degrees of straight up (the cabin's ceiling), and from farther
    // away only past a fold.
    TubeSpec spec;
    spec.foldSpacingMm = 8.0;
    spec.foldFirstMm = 16.0;
    spec.foldLastMm = 64.0;
    testing_support::GpuScene scene(context(), testing_support::tubeVolume(spec));
    const colon::WallSurface wall = colon::colonWallSurface(scene.volume, testing_support::airMask(scene.volume));
    const auto poses = axisPoses(spec, 12.0, 68.0, 2.0);
    const auto none = cover(scene, wall, smallDisplay("ic5", conformal::MapKind::None, 10), poses);
    const auto conformalMap = cover(scene, wall, smallDisplay("ic5", conformal::MapKind::Conformal, 10), poses);
    const auto ic6 = cover(scene, wall, smallDisplay("ic6", conformal::MapKind::None, 10), poses);
    EXPECT_LT(none->percent(), ic6->percent() - 3.0);
    EXPECT_NEAR(conformalMap->percent(), ic6->percent(), 1.0);
    // What ic6 sees and ic5 without the map does not lies in the tube's top, toward the ceiling.
    double missed = 0.0, missedOnTop = 0.0;
    for (std::size_t e = 0; e < wall.size(); ++e) {
        if (ic6->seen()[e] == 0 || none->seen()[e] != 0) continue;
        missed += wall.areaMm2[e];
        if (wall.centreMm[e].y > 0.5 * spec.extentMm.y + 2.0) missedOnTop += wall.areaMm2[e];
    }
    EXPECT_GT(missed, 0.0);
    EXPECT_GT(missedOnTop, 0.9 * missed);
}

}  // namespace
