// The stereo eyes' rays. The map about each eye (the display default): every ray runs straight
// from its eye along the map's scene direction for its display direction, so each eye sees the
// conformal image of its own view. The warp of space about the map centre: the polyline
// (shaders/polyline_warp.glsl) against the exact warp, which maps every sample: for the stereo
// eyes it follows the bent rays to a fraction of a pixel where the paper's single chord strays
// by several; for the centre eye it is the chord; its table gives the per-ray image on every
// pose; the tile pass and empty-space skipping leave its image as it is.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "conformal/cube_map.h"
#include "conformal/cube_map_baker.h"
#include "engine/display/display.h"
#include "engine/render/raycaster.h"
#include "tests/support/ball_room.h"
#include "tests/support/gpu_test_fixture.h"
#include "tests/support/image_compare.h"
#include "volumes/analytic_phantom.h"

namespace {

using engine::Eye;
using engine::WarpMode;
using testing_support::BallRoom;
using testing_support::ballRoomSettings;
using testing_support::colorDifference;
using testing_support::fiveWallCube;
using testing_support::percentile;

/// A small spherical room, 20 mm in radius: seen from near its centre by eyes 0.65 mm to either
/// side (a 0.065 m eye separation at 20 mm per metre), its wall lies 15 to 40 times the eye's
/// offset away, where the stereo eyes' rays are bent most unlike a chord.
volumes::BallSpec smallRoom() {
    volumes::BallSpec room;
    room.grid.dims = {128, 128, 128};
    room.grid.spacingMm = glm::dvec3(0.4);
    room.centreMm = glm::dvec3(25.4);
    room.radiusMm = 20.0;
    room.edgeWidthMm = 0.8;
    room.insideHu = -1000;
    room.outsideHu = 40;
    return room;
}

engine::ScenePose roomPose() {
    engine::ScenePose pose;
    pose.positionMm = smallRoom().centreMm + glm::dvec3(1.5, -1.0, 0.5);
    pose.forward = glm::normalize(glm::dvec3(0.2, -0.1, 1.0));  // not axis-aligned on purpose
    pose.up = {0.0, 1.0, 0.0};
    pose.mmPerMetre = 20.0;
    return pose;
}

/// Per pixel hit by both images, the distance between the two hits as an angle seen from the eye
/// at the reference's hit, degrees.
std::vector<double> hitDistancesDeg(const engine::RenderedImage& image, const engine::RenderedImage& reference,
                                    const engine::ViewRays& rays) {
    std::vector<double> distances;
    for (std::size_t p = 0; p + 3 < image.hitMm.size(); p += 4) {
        if (image.hitMm[p + 3] < 0.5f || reference.hitMm[p + 3] < 0.5f) continue;
        const glm::dvec3 a(image.hitMm[p], image.hitMm[p + 1], image.hitMm[p + 2]);
        const glm::dvec3 b(reference.hitMm[p], reference.hitMm[p + 1], reference.hitMm[p + 2]);
        distances.push_back(glm::degrees(glm::length(a - b) / glm::length(b - rays.eyeMm)));
    }
    return distances;
}

double mean(const std::vector<double>& values) {
    double sum = 0.0;
    for (double v : values) sum += v;
    return values.empty() ? 0.0 : sum / static_cast<double>(values.size());
}

class PolylineWarp : public testing_support::GpuTest {
protected:
    static void SetUpTestSuite() {
        GpuTest::SetUpTestSuite();
        conformal::BakeSettings bake;
        bake.box.size = glm::dvec3(2.4);
        bake.size = 256;
        bake.mesh.resolution = 48;
        bake.kind = conformal::MapKind::Conformal;
        sMap = std::make_unique<conformal::CubeMap>(conformal::bakeCubeMap(bake));
    }
    static inline std::unique_ptr<conformal::CubeMap> sMap;
};

/// Per pixel, the largest colour-channel difference between two images of one size.
std::vector<double> pixelDifferences(const engine::RenderedImage& a, const engine::RenderedImage& b) {
    std::vector<double> differences;
    for (std::size_t p = 0; p + 3 < a.rgba.size(); p += 4) {
        int largest = 0;
        for (std::size_t c = 0; c < 3; ++c) largest = std::max(largest, std::abs(a.rgba[p + c] - b.rgba[p + c]));
        differences.push_back(largest);
    }
    return differences;
}

// Both stereo eyes, every wall: seen from the eye, the polyline's hits lie within about a tenth
// of a degree of the exact warp's at p99, the chord's more than eight times further. The room's
// wall lies 15 to 40 times the eye's offset away, where the curve bends most unlike a straight
// line (polyline_warp.glsl); at the cabin's scale of 10 mm per metre that is 5 to 13 mm from the
// eye, nearer than a colon's wall usually is.
TEST_F(PolylineWarp, FollowsTheExactWarpForBothEyesWhereTheChordDoesNot) {
    BallRoom room(context(), smallRoom());
    room.raycaster.setCubeMap(sMap->size, sMap->rgba);
    const engine::Display display = fiveWallCube(96);
    const engine::ScenePose pose = roomPose();
    std::vector<double> polylineErrors, chordErrors, polylineColours, chordColours;
    for (Eye eye : {Eye::Left, Eye::Right}) {
        for (const auto& wall : display.walls) {
            const auto exact = engine::wallView(display, wall.name, eye, pose, WarpMode::Exact);
            const auto polyline = engine::wallView(display, wall.name, eye, pose, WarpMode::Polyline);
            const auto chord = engine::wallView(display, wall.name, eye, pose, WarpMode::Chord);
            const auto exactImage = room.raycaster.render(exact.rays, ballRoomSettings(), exact.warp);
            const auto polylineImage = room.raycaster.render(polyline.rays, ballRoomSettings(), polyline.warp);
            const auto chordImage = room.raycaster.render(chord.rays, ballRoomSettings(), chord.warp);
            const std::vector<double> toPolyline = hitDistancesDeg(polylineImage, exactImage, exact.rays);
            const std::vector<double> toChord = hitDistancesDeg(chordImage, exactImage, exact.rays);
            // The room's wall fills every wall of the display.
            ASSERT_GT(toPolyline.size(), 0.95 * 96 * 96) << engine::wallNameText(wall.name) << " " << engine::eyeText(eye);
            polylineErrors.insert(polylineErrors.end(), toPolyline.begin(), toPolyline.end());
            chordErrors.insert(chordErrors.end(), toChord.begin(), toChord.end());
            const std::vector<double> polylineDifference = pixelDifferences(polylineImage, exactImage);
            const std::vector<double> chordDifference = pixelDifferences(chordImage, exactImage);
            polylineColours.insert(polylineColours.end(), polylineDifference.begin(), polylineDifference.end());
            chordColours.insert(chordColours.end(), chordDifference.begin(), chordDifference.end());
        }
    }
    const double polylineP99 = percentile(polylineErrors, 0.99), chordP99 = percentile(chordErrors, 0.99);
    std::cout << "hit distance to the exact warp, degrees at p50/p99/max: polyline " << percentile(polylineErrors, 0.5)
              << " / " << polylineP99 << " / " << percentile(polylineErrors, 1.0) << ", chord "
              << percentile(chordErrors, 0.5) << " / " << chordP99 << " / " << percentile(chordErrors, 1.0)
              << "; colour levels at p99: polyline " << percentile(polylineColours, 0.99) << ", chord "
              << percentile(chordColours, 0.99) << ", mean: polyline " << mean(polylineColours) << ", chord "
              << mean(chordColours) << '\n';
    EXPECT_LT(polylineP99, 0.2);
    EXPECT_GT(chordP99, 8.0 * polylineP99);  // what the polyline is for: the chord is far off here
    EXPECT_LT(percentile(polylineErrors, 0.999), 1.0);
    EXPECT_LE(percentile(polylineColours, 0.99), 2.0);
    EXPECT_LT(mean(polylineColours), 0.4 * mean(chordColours));
}

// The map about each eye: seen from its own eye, every pixel's first hit lies along the map's
// scene direction for the pixel's display direction (from that eye), F sampled on the CPU from
// the same cube map; and the two eyes' hits differ where the warp of space about the centre
// would make them agree with the centre eye's bent rays.
TEST_F(PolylineWarp, EyeCentredRaysRunFromEachEyeAlongTheMap) {
    BallRoom room(context(), smallRoom());
    room.raycaster.setCubeMap(sMap->size, sMap->rgba);
    const engine::Display display = fiveWallCube(64);
    const engine::ScenePose pose = roomPose();
    const glm::dmat3 toVolume = engine::caveToVolumeRotation(pose);
    for (Eye eye : {Eye::Left, Eye::Right}) {
        double worstDeg = 0.0;
        int hits = 0;
        for (const auto& wall : display.walls) {
            const auto view = engine::wallView(display, wall.name, eye, pose, WarpMode::EyeCentred);
            ASSERT_EQ(view.warp.mode, WarpMode::Chord);  // a chord about the eye
            ASSERT_LT(glm::length(view.warp.mapCentreMm - view.rays.eyeMm), 1e-12);
            const auto image = room.raycaster.render(view.rays, ballRoomSettings(), view.warp);
            for (int y = 0; y < image.height; ++y) {
                for (int x = 0; x < image.width; ++x) {
                    const std::size_t i = 4 * (static_cast<std::size_t>(y) * image.width + x);
                    if (image.hitMm[i + 3] < 0.5f) continue;
                    const glm::dvec3 hit(image.hitMm[i], image.hitMm[i + 1], image.hitMm[i + 2]);
                    const glm::dvec3 displayCave = glm::transpose(toVolume) * engine::rayDirectionOf(view.rays, x, y);
                    const glm::dvec3 scene = toVolume * glm::normalize(glm::dvec3(conformal::sampleCubeMapBilinear(*sMap, displayCave)));
                    const double angle = std::acos(std::clamp(glm::dot(glm::normalize(hit - view.rays.eyeMm), scene), -1.0, 1.0));
                    worstDeg = std::max(worstDeg, glm::degrees(angle));
                    ++hits;
                }
            }
        }
        EXPECT_EQ(hits, 5 * 64 * 64) << engine::eyeText(eye);
        EXPECT_LT(worstDeg, 0.02) << engine::eyeText(eye);
    }
    // The centre eye's rays are the chord's about the map centre, pixel for pixel.
    const auto centred = engine::wallView(display, engine::WallName::Front, Eye::Centre, pose, WarpMode::EyeCentred);
    const auto chord = engine::wallView(display, engine::WallName::Front, Eye::Centre, pose, WarpMode::Chord);
    EXPECT_EQ(room.raycaster.render(centred.rays, ballRoomSettings(), centred.warp).rgba,
              room.raycaster.render(chord.rays, ballRoomSettings(), chord.warp).rgba);
    // The ray caster itself never takes the display-level mode.
    EXPECT_THROW(room.raycaster.render(centred.rays, ballRoomSettings(), engine::Warp{WarpMode::EyeCentred, pose.positionMm,
                                                                                     toVolume}),
                 std::logic_error);
}

// For the centre eye the ray is not bent: the polyline is the chord, pixel for pixel (the ray
// caster renders it as one), and an eye a hair from the centre, which takes the polyline's own
// code, keeps one piece and the chord's image.
TEST_F(PolylineWarp, IsTheChordForTheCentreEye) {
    BallRoom room(context(), smallRoom());
    room.raycaster.setCubeMap(sMap->size, sMap->rgba);
    const engine::Display display = fiveWallCube(64);
    engine::Display nudged = display;
    nudged.headPositionM = glm::dvec3(1e-6, 0.0, 0.0);  // 0.02 micrometres at 20 mm per metre
    const engine::ScenePose pose = roomPose();
    for (const auto& wall : display.walls) {
        const auto chord = engine::wallView(display, wall.name, Eye::Centre, pose, WarpMode::Chord);
        const auto polyline = engine::wallView(display, wall.name, Eye::Centre, pose, WarpMode::Polyline);
        const auto chordImage = room.raycaster.render(chord.rays, ballRoomSettings(), chord.warp);
        const auto polylineImage = room.raycaster.render(polyline.rays, ballRoomSettings(), polyline.warp);
        EXPECT_EQ(polylineImage.rgba, chordImage.rgba) << engine::wallNameText(wall.name);
        EXPECT_EQ(polylineImage.hitMm, chordImage.hitMm) << engine::wallNameText(wall.name);
        const auto off = engine::wallView(nudged, wall.name, Eye::Centre, pose, WarpMode::Polyline);
        const auto offImage = room.raycaster.render(off.rays, ballRoomSettings(), off.warp);
        const auto [worst, mean] = colorDifference(offImage, chordImage);
        EXPECT_LE(worst, 1) << engine::wallNameText(wall.name);
        EXPECT_LT(percentile(hitDistancesDeg(offImage, chordImage, chord.rays), 1.0), 1e-3)
            << engine::wallNameText(wall.name);
    }
    // The chord's table and the polyline's: one each for the nudged eye, none more for the centre.
    EXPECT_EQ(room.raycaster.chordTableCount(), 2u * display.walls.size());
}

// The table is filled once per wall and eye and read on every later pose: the same image as the
// polylines made per ray, but for float rounding, and whichever pose filled it.
TEST_F(PolylineWarp, TableGivesThePerRayImageOnEveryPose) {
    BallRoom room(context(), smallRoom());
    room.raycaster.setCubeMap(sMap->size, sMap->rgba);
    const engine::Display display = fiveWallCube(72);
    engine::RenderSettings perRay = ballRoomSettings();
    perRay.isUsingChordTable = false;
    engine::ScenePose pose = roomPose();
    for (int frame = 0; frame < 2; ++frame) {
        for (Eye eye : {Eye::Left, Eye::Right}) {
            const auto view = engine::wallView(display, engine::WallName::Front, eye, pose, WarpMode::Polyline);
            const auto read = room.raycaster.render(view.rays, ballRoomSettings(), view.warp);
            const auto made = room.raycaster.render(view.rays, perRay, view.warp);
            const std::string what = "frame " + std::to_string(frame) + " " + engine::eyeText(eye);
            const auto [worst, mean] = colorDifference(read, made);
            EXPECT_LE(worst, 1) << what;
            EXPECT_LT(mean, 0.01) << what;
            EXPECT_LT(percentile(hitDistancesDeg(read, made, view.rays), 1.0), 1e-3) << what;
        }
        pose.positionMm += glm::dvec3(-2.0, 1.5, 2.0);  // moved and turned: the tables are read
        pose.forward = glm::normalize(glm::dvec3(-0.5, 0.2, 1.0));
    }
    EXPECT_EQ(room.raycaster.chordTableCount(), 2u);
}

// Skipping empty space along the polyline's pieces, from the tile pass's start and by the
// march's own looks, changes no sample a march without skipping takes (a fixed step keeps the
// samples on the same grid): the images agree but for float rounding of where a skip lands.
// The room is mostly empty, so both skip far; the fetches show that they do.
TEST_F(PolylineWarp, SkippingLeavesTheImageAsItIs) {
    BallRoom room(context(), smallRoom());
    room.raycaster.setCubeMap(sMap->size, sMap->rgba);
    const engine::Display display = fiveWallCube(80);
    const engine::ScenePose pose = roomPose();
    engine::RenderSettings tilePass = ballRoomSettings();
    tilePass.isCountingFetches = true;
    engine::RenderSettings looksOnly = tilePass;
    looksOnly.isUsingRayStartPass = false;
    engine::RenderSettings noSkipping = tilePass;
    noSkipping.isSkipping = false;
    for (Eye eye : {Eye::Left, Eye::Right}) {
        for (const auto& wall : display.walls) {
            const auto view = engine::wallView(display, wall.name, eye, pose, WarpMode::Polyline);
            const auto plain = room.raycaster.render(view.rays, noSkipping, view.warp);
            const std::string what = engine::wallNameText(wall.name) + " " + engine::eyeText(eye);
            for (const auto& settings : {tilePass, looksOnly}) {
                const auto skipped = room.raycaster.render(view.rays, settings, view.warp);
                const auto [worst, mean] = colorDifference(skipped, plain);
                EXPECT_LE(worst, 2) << what;
                EXPECT_LT(mean, 0.01) << what;
                const double fetches = engine::fetchCountsOf(skipped).total, plainFetches = engine::fetchCountsOf(plain).total;
                EXPECT_LT(fetches, 0.6 * plainFetches) << what << (settings.isUsingRayStartPass ? ", tile pass" : ", looks");
            }
        }
    }
}

}  // namespace
