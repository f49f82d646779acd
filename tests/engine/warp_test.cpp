// Rays of display walls, bent and unbent: a 6-wall CAVE equals pinhole cameras; chord mode
// equals exact mode for the centre eye; through the conformal map the walls keep angles
// (quasi-conformal distortion K ~ 1, measured from the hit-position images), through the
// linear baseline they do not.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "conformal/cube_map_baker.h"
#include "engine/display/display.h"
#include "engine/render/raycaster.h"
#include "tests/support/ball_room.h"
#include "tests/support/gpu_test_fixture.h"
#include "tests/support/image_compare.h"
#include "volumes/analytic_phantom.h"

namespace {

using testing_support::BallRoom;
using testing_support::ballRoomSettings;
using testing_support::colorDifference;
using testing_support::fiveWallCube;
using testing_support::percentile;

using engine::WallName;

/// A spherical room: air inside radius 90 mm around the volume's centre, tissue outside, so
/// every ray from the centre ends on a sphere whose hit gives its scene direction exactly.
volumes::BallSpec sphericalRoom() {
    volumes::BallSpec room;
    room.grid.dims = {200, 200, 200};
    room.centreMm = glm::dvec3(99.5);
    room.radiusMm = 90.0;
    room.insideHu = -1000;
    room.outsideHu = 40;
    return room;
}

engine::ScenePose poseAt(const glm::dvec3& positionMm) {
    engine::ScenePose pose;
    pose.positionMm = positionMm;
    pose.forward = glm::normalize(glm::dvec3(0.2, -0.1, 1.0));  // not axis-aligned on purpose
    pose.up = {0.0, 1.0, 0.0};
    pose.mmPerMetre = 20.0;
    return pose;
}

class WarpedWalls : public testing_support::GpuTest {
protected:
    static void SetUpTestSuite() {
        GpuTest::SetUpTestSuite();
        conformal::BakeSettings bake;
        bake.box.size = glm::dvec3(2.4);
        bake.size = 192;
        bake.mesh.resolution = 48;
        bake.kind = conformal::MapKind::Conformal;
        sConformal = std::make_unique<conformal::CubeMap>(conformal::bakeCubeMap(bake));
        bake.kind = conformal::MapKind::Linear;
        sLinear = std::make_unique<conformal::CubeMap>(conformal::bakeCubeMap(bake));
    }
    static inline std::unique_ptr<conformal::CubeMap> sConformal;
    static inline std::unique_ptr<conformal::CubeMap> sLinear;
};


TEST_F(WarpedWalls, SixWallDisplayEqualsPinholeCameras) {
    BallRoom room(context(), sphericalRoom());
    engine::Display cave = engine::displayPreset("cave6");
    for (auto& wall : cave.walls) wall.width = wall.height = 96;
    cave.nearM = 0.01;
    // Off-centre, so each wall sees a different part of the room's sphere.
    const auto pose = poseAt(glm::dvec3(70.0, 120.0, 95.0));
    const glm::dmat3 rotation = engine::caveToVolumeRotation(pose);
    for (const auto& wall : cave.walls) {
        const auto view = engine::wallView(cave, wall.name, engine::Eye::Centre, pose, engine::WarpMode::Chord);
        EXPECT_EQ(view.warp.mode, engine::WarpMode::None);  // a 6-wall display bends nothing
        const auto rect = engine::wallRectangle(cave, wall.name);
        engine::PinholeCamera camera;
        camera.positionMm = pose.positionMm;
        camera.lookAtMm = pose.positionMm + rotation * (rect.topLeftM + 0.5 * (rect.widthM + rect.heightM));
        camera.up = rotation * -rect.heightM;
        camera.verticalFovDeg = 90.0;
        camera.width = camera.height = 96;
        const auto fromWall = room.raycaster.render(view.rays, ballRoomSettings(), view.warp);
        const auto fromCamera = room.raycaster.render(engine::viewRaysFrom(camera), ballRoomSettings());
        const auto [worst, mean] = colorDifference(fromWall, fromCamera);
        EXPECT_LE(worst, 2) << engine::wallNameText(wall.name);
        EXPECT_LT(mean, 0.02) << engine::wallNameText(wall.name);
    }
}

TEST_F(WarpedWalls, ChordEqualsExactForTheCentreEye) {
    BallRoom room(context(), sphericalRoom());
    room.raycaster.setCubeMap(sConformal->size, sConformal->rgba);
    const engine::Display display = fiveWallCube(80);
    const auto pose = poseAt(sphericalRoom().centreMm + glm::dvec3(3.0, -2.0, 1.0));
    for (const auto& wall : display.walls) {
        const auto chord = engine::wallView(display, wall.name, engine::Eye::Centre, pose, engine::WarpMode::Chord);
        const auto exact = engine::wallView(display, wall.name, engine::Eye::Centre, pose, engine::WarpMode::Exact);
        const auto chordImage = room.raycaster.render(chord.rays, ballRoomSettings(), chord.warp);
        const auto exactImage = room.raycaster.render(exact.rays, ballRoomSettings(), exact.warp);
        const auto [worst, mean] = colorDifference(chordImage, exactImage);
        EXPECT_LE(worst, 2) << engine::wallNameText(wall.name);
        EXPECT_LT(mean, 0.05) << engine::wallNameText(wall.name);
        double worstMm = 0.0;
        for (std::size_t i = 0; i < chordImage.hitMm.size(); ++i) {
            worstMm = std::max(worstMm, static_cast<double>(std::abs(chordImage.hitMm[i] - exactImage.hitMm[i])));
        }
        EXPECT_LT(worstMm, 0.05) << engine::wallNameText(wall.name);
    }
}

/// Largest difference of two hit-position images, millimetres.
double worstHitDifferenceMm(const engine::RenderedImage& a, const engine::RenderedImage& b) {
    double worstMm = 0.0;
    for (std::size_t i = 0; i < a.hitMm.size(); ++i) {
        worstMm = std::max(worstMm, static_cast<double>(std::abs(a.hitMm[i] - b.hitMm[i])));
    }
    return worstMm;
}

/// Whether `read` (through a chord table) is the per-ray fetches' image `fetched` but for float
/// rounding: the table's texels were looked up along the display's own directions, the per-ray
/// ones along the same directions turned into the volume and back.
void expectSameButRounding(const engine::RenderedImage& read, const engine::RenderedImage& fetched, const std::string& what) {
    const auto [worst, mean] = colorDifference(read, fetched);
    EXPECT_LE(worst, 1) << what;
    EXPECT_LT(mean, 0.01) << what;
    EXPECT_LT(worstHitDifferenceMm(read, fetched), 1e-3) << what;
}

// The chord table holds each pixel's cube-map texels for one display geometry (wall, eye,
// scale). It must give the per-ray fetches' image on the frame that fills it and on later
// poses, which read it; the images must not depend on which pose filled it (a resumed run or
// another rank starts elsewhere); another eye or wall is another table, and a new cube map
// drops them all.
TEST_F(WarpedWalls, ChordTableGivesThePerRayImageOnEveryPose) {
    BallRoom room(context(), sphericalRoom());
    room.raycaster.setCubeMap(sConformal->size, sConformal->rgba);
    const engine::Display display = fiveWallCube(72);
    engine::RenderSettings perRay = ballRoomSettings();
    perRay.isUsingChordTable = false;
    const engine::RenderSettings withTable = ballRoomSettings();
    auto pose = poseAt(sphericalRoom().centreMm + glm::dvec3(3.0, -2.0, 1.0));
    const auto left = engine::wallView(display, WallName::Front, engine::Eye::Left, pose, engine::WarpMode::Chord);
    const auto fetched = room.raycaster.render(left.rays, perRay, left.warp);
    EXPECT_EQ(room.raycaster.chordTableCount(), 0u);
    const auto filled = room.raycaster.render(left.rays, withTable, left.warp);
    EXPECT_EQ(room.raycaster.chordTableCount(), 1u);
    expectSameButRounding(filled, fetched, "the frame that fills the table");

    // Moved and turned: the same wall and eye in CAVE space, so the table is read.
    pose.positionMm += glm::dvec3(-6.0, 4.0, 5.0);
    pose.forward = glm::normalize(glm::dvec3(-0.5, 0.2, 1.0));
    const auto moved = engine::wallView(display, WallName::Front, engine::Eye::Left, pose, engine::WarpMode::Chord);
    const auto movedRead = room.raycaster.render(moved.rays, withTable, moved.warp);
    EXPECT_EQ(room.raycaster.chordTableCount(), 1u);
    expectSameButRounding(movedRead, room.raycaster.render(moved.rays, perRay, moved.warp), "a later pose");
    // The pose did move the image: a table read for the first pose's rays would show it.
    EXPECT_GT(worstHitDifferenceMm(movedRead, filled), 1.0);
    // A ray caster that starts at the later pose fills the table there: the same bytes.
    BallRoom fresh(context(), sphericalRoom());
    fresh.raycaster.setCubeMap(sConformal->size, sConformal->rgba);
    const auto movedFilled = fresh.raycaster.render(moved.rays, withTable, moved.warp);
    EXPECT_EQ(movedFilled.rgba, movedRead.rgba);
    EXPECT_EQ(movedFilled.hitMm, movedRead.hitMm);
    // With no memory for tables, each frame fills one of its own: the same bytes again.
    fresh.raycaster.setCubeMap(sConformal->size, sConformal->rgba);
    fresh.raycaster.setChordTableBudget(0);
    const auto unkept = fresh.raycaster.render(moved.rays, withTable, moved.warp);
    EXPECT_EQ(fresh.raycaster.chordTableCount(), 0u);
    EXPECT_EQ(unkept.rgba, movedRead.rgba);
    EXPECT_EQ(unkept.hitMm, movedRead.hitMm);

    // The other eye and another wall have their own chord ends.
    for (const auto& [wall, eye] : {std::pair{WallName::Front, engine::Eye::Right}, std::pair{WallName::Left, engine::Eye::Left}}) {
        const auto view = engine::wallView(display, wall, eye, pose, engine::WarpMode::Chord);
        expectSameButRounding(room.raycaster.render(view.rays, withTable, view.warp),
                              room.raycaster.render(view.rays, perRay, view.warp), engine::wallNameText(wall));
    }
    EXPECT_EQ(room.raycaster.chordTableCount(), 3u);
    // The adaptive step reads the map's local scale from the table too. Its steps show in the
    // volume fetches each ray makes (a wrong scale hardly moves the refined hits).
    engine::RenderSettings adaptivePerRay = perRay;
    adaptivePerRay.isAdaptive = true;
    adaptivePerRay.maxStepVoxels = 8.0;
    adaptivePerRay.isCountingFetches = true;
    engine::RenderSettings adaptiveWithTable = adaptivePerRay;
    adaptiveWithTable.isUsingChordTable = true;
    const auto fetchesOf = [](const engine::RenderedImage& image) {
        double fetches = 0.0;
        for (std::size_t i = 3; i < image.hitMm.size(); i += 4) fetches += image.hitMm[i];
        return fetches;
    };
    const double tableFetches = fetchesOf(room.raycaster.render(moved.rays, adaptiveWithTable, moved.warp));
    const double perRayFetches = fetchesOf(room.raycaster.render(moved.rays, adaptivePerRay, moved.warp));
    EXPECT_NEAR(tableFetches / perRayFetches, 1.0, 1e-3) << tableFetches << " fetches against " << perRayFetches;
    EXPECT_EQ(room.raycaster.chordTableCount(), 3u);
    // A map centre outside the volume: the chord's reach would change with the pose, so no
    // table is kept and the rays fetch per ray.
    auto outside = pose;
    outside.positionMm = glm::dvec3(-30.0, 100.0, 100.0);
    const auto away = engine::wallView(display, WallName::Front, engine::Eye::Left, outside, engine::WarpMode::Chord);
    const auto awayImage = room.raycaster.render(away.rays, withTable, away.warp);
    EXPECT_EQ(room.raycaster.chordTableCount(), 3u);
    EXPECT_EQ(awayImage.rgba, room.raycaster.render(away.rays, perRay, away.warp).rgba);
    room.raycaster.setCubeMap(sLinear->size, sLinear->rgba);
    EXPECT_EQ(room.raycaster.chordTableCount(), 0u);
}

/// Quasi-conformal distortion K = sigma_max / sigma_min of the map from display directions
/// (pixel centres seen from the map centre) to scene directions (hits seen from the eye at the
/// centre), by central differences `h` pixels wide, at every pixel at least `margin` from the
/// image border. Tangent bases are built at both ends, so the wall's own perspective cancels.
std::vector<double> distortionOf(const engine::WallView& view, const engine::RenderedImage& image, int h, int margin) {
    const glm::dvec3 c = view.warp.mapCentreMm;
    const auto display = [&](double x, double y) {
        const glm::dvec3 p = view.rays.wallOriginMm + (x + 0.5) / view.rays.width * view.rays.wallUMm +
                             (y + 0.5) / view.rays.height * view.rays.wallVMm;
        return glm::normalize(p - c);
    };
    const auto scene = [&](int x, int y) {
        const std::size_t i = 4 * (static_cast<std::size_t>(y) * image.width + x);
        return glm::normalize(glm::dvec3(image.hitMm[i], image.hitMm[i + 1], image.hitMm[i + 2]) - c);
    };
    std::vector<double> ks;
    for (int y = margin; y < image.height - margin; ++y) {
        for (int x = margin; x < image.width - margin; ++x) {
            const glm::dvec3 dx = (display(x + h, y) - display(x - h, y)) / (2.0 * h);
            const glm::dvec3 dy = (display(x, y + h) - display(x, y - h)) / (2.0 * h);
            const glm::dvec3 sx = (scene(x + h, y) - scene(x - h, y)) / (2.0 * h);
            const glm::dvec3 sy = (scene(x, y + h) - scene(x, y - h)) / (2.0 * h);
            // Orthonormal tangent frames, then the 2x2 Jacobian J = S * D^-1.
            const auto frame = [](const glm::dvec3& a, const glm::dvec3& b, glm::dmat2& m) {
                const glm::dvec3 e1 = glm::normalize(a);
                const glm::dvec3 e2 = glm::normalize(b - glm::dot(b, e1) * e1);
                m = glm::dmat2(glm::dot(a, e1), glm::dot(a, e2), glm::dot(b, e1), glm::dot(b, e2));
            };
            glm::dmat2 displayJacobian, sceneJacobian;
            frame(dx, dy, displayJacobian);
            frame(sx, sy, sceneJacobian);
            const glm::dmat2 j = sceneJacobian * glm::inverse(displayJacobian);
            // Singular values of a 2x2 matrix from its Frobenius norm and determinant.
            const double frobenius2 = j[0][0] * j[0][0] + j[0][1] * j[0][1] + j[1][0] * j[1][0] + j[1][1] * j[1][1];
            const double det = std::abs(glm::determinant(j));
            const double root = std::sqrt(std::max(frobenius2 * frobenius2 - 4.0 * det * det, 0.0));
            const double sMax = std::sqrt(0.5 * (frobenius2 + root));
            const double sMin = det / sMax;
            ks.push_back(sMax / sMin);
        }
    }
    return ks;
}

TEST_F(WarpedWalls, ConformalMapKeepsAnglesLinearMapDoesNot) {
    BallRoom room(context(), sphericalRoom());
    const engine::Display display = fiveWallCube(128);
    const auto pose = poseAt(sphericalRoom().centreMm);
    engine::RenderSettings settings = ballRoomSettings();
    settings.stepVoxels = 0.25;
    for (const conformal::CubeMap* map : {sConformal.get(), sLinear.get()}) {
        room.raycaster.setCubeMap(map->size, map->rgba);
        std::vector<double> ks;
        for (const auto& wall : display.walls) {
            const auto view = engine::wallView(display, wall.name, engine::Eye::Centre, pose, engine::WarpMode::Chord);
            const auto image = room.raycaster.render(view.rays, settings, view.warp);
            const auto wallKs = distortionOf(view, image, 4, 6);
            ks.insert(ks.end(), wallKs.begin(), wallKs.end());
        }
        const double median = percentile(ks, 0.5), p90 = percentile(ks, 0.9);
        const bool isConformal = map->kind == conformal::MapKind::Conformal;
        std::cout << (isConformal ? "conformal" : "linear") << " map on the walls: K median " << median << ", p90 "
                  << p90 << ", max " << percentile(ks, 1.0) << " over " << ks.size() << " pixels\n";
        if (isConformal) {
            EXPECT_LT(median, 1.01);
            EXPECT_LT(p90, 1.05);
        } else {
            EXPECT_GT(median, 1.2);
            EXPECT_GT(p90, 1.3);
        }
    }
}

TEST_F(WarpedWalls, Cave4ThroughTheMapShowsWhatIsBehindOnItsWallsAndKeepsAngles) {
    // The classic 4-wall CAVE lacks the ceiling and the back: the map opens both onto the front,
    // side walls and floor.
    conformal::BakeSettings bake;
    bake.box.size = glm::dvec3(2.4);
    bake.box.missingFaces = conformal::faceBit(conformal::kCeilingFace) | conformal::faceBit(4);
    bake.size = 192;
    bake.mesh.resolution = 48;
    const conformal::CubeMap map = conformal::bakeCubeMap(bake);
    BallRoom room(context(), sphericalRoom());
    room.raycaster.setCubeMap(map.size, map.rgba);
    engine::Display display = engine::displayPreset("cave4");
    for (auto& wall : display.walls) wall.width = wall.height = 96;
    const auto pose = poseAt(sphericalRoom().centreMm);
    engine::RenderSettings settings = ballRoomSettings();
    settings.stepVoxels = 0.25;
    // Scene directions seen on the walls, from the hits about the map centre.
    double nearestBehind = 10.0;
    std::vector<double> ks;
    for (const engine::Eye eye : {engine::Eye::Left, engine::Eye::Right, engine::Eye::Centre}) {
        for (const auto& wall : display.walls) {
            const auto view = engine::wallView(display, wall.name, eye, pose, engine::WarpMode::Chord);
            const auto image = room.raycaster.render(view.rays, settings, view.warp);
            ASSERT_EQ(image.width, 96);
            int hits = 0;
            for (std::size_t i = 0; i < image.hitMm.size(); i += 4) {
                const glm::dvec3 hit(image.hitMm[i], image.hitMm[i + 1], image.hitMm[i + 2]);
                if (!(std::isfinite(hit.x) && glm::length(hit - sphericalRoom().centreMm) > 80.0)) continue;
                ++hits;
                const glm::dvec3 scene = glm::normalize(hit - view.warp.mapCentreMm);
                nearestBehind = std::min(nearestBehind, std::acos(std::clamp(glm::dot(scene, -pose.forward), -1.0, 1.0)));
            }
            // Every pixel of every wall, for both eyes, ends on the room's sphere.
            EXPECT_EQ(hits, 96 * 96) << engine::wallNameText(wall.name) << " " << engine::eyeText(eye);
            if (eye == engine::Eye::Centre) {
                const auto wallKs = distortionOf(view, image, 3, 5);
                ks.insert(ks.end(), wallKs.begin(), wallKs.end());
            }
        }
    }
    // Straight behind the viewer (the back wall's centre, which cave4 lacks) is on a wall.
    EXPECT_LT(glm::degrees(nearestBehind), 3.0);
    const double median = percentile(ks, 0.5), p90 = percentile(ks, 0.9);
    std::cout << "cave4 through the conformal map: K median " << median << ", p90 " << p90 << " over " << ks.size()
              << " pixels\n";
    EXPECT_LT(median, 1.01);
    EXPECT_LT(p90, 1.05);
}

}  // namespace
