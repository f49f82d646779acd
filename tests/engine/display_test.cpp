// Display geometry without a device: presets, wall rectangles, eyes, the CAVE's pose in a
// volume, and the rays of a wall.
#include <random>

#include <gtest/gtest.h>

#include "engine/display/display.h"

namespace {

using engine::WallName;

constexpr WallName kAllWalls[] = {WallName::Front, WallName::Back, WallName::Left,
                                  WallName::Right, WallName::Floor, WallName::Ceiling};

/// Ray parameter and face coordinates where the ray from the centre along `d` meets the
/// wall's plane; the wall is hit when t > 0 and both coordinates are in [0, 1].
bool hitsWall(const engine::Display& display, WallName wall, const glm::dvec3& d) {
    const auto rect = engine::wallRectangle(display, wall);
    // Solve topLeft + a * width + b * height = t * d.
    const glm::dmat3 system(rect.widthM, rect.heightM, -d);
    const glm::dvec3 abt = glm::inverse(system) * (-rect.topLeftM);
    return abt.z > 0.0 && abt.x >= 0.0 && abt.x <= 1.0 && abt.y >= 0.0 && abt.y <= 1.0;
}

TEST(DisplayGeometry, Cave6WallsTileTheSphereOfDirections) {
    const engine::Display cave = engine::displayPreset("cave6");
    std::mt19937 random(3);
    std::normal_distribution<double> gauss;
    for (int i = 0; i < 20000; ++i) {
        const glm::dvec3 d = glm::normalize(glm::dvec3(gauss(random), gauss(random), gauss(random)));
        int walls = 0;
        for (WallName wall : kAllWalls) walls += hitsWall(cave, wall, d) ? 1 : 0;
        ASSERT_EQ(walls, 1) << "direction " << d.x << "," << d.y << "," << d.z;
    }
}

TEST(DisplayGeometry, WallsFaceTheViewerAndUnfoldAsACross) {
    const engine::Display ic5 = engine::displayPreset("ic5");
    for (WallName wall : kAllWalls) {
        const auto rect = engine::wallRectangle(ic5, wall);
        // Image right x image down points into the wall, away from the viewer at the centre, on
        // every wall alike: no wall is seen mirrored.
        const glm::dvec3 centre = rect.topLeftM + 0.5 * (rect.widthM + rect.heightM);
        EXPECT_GT(glm::dot(glm::cross(rect.widthM, rect.heightM), centre), 0.0) << engine::wallNameText(wall);
    }
    const auto front = engine::wallRectangle(ic5, WallName::Front);
    const auto floor = engine::wallRectangle(ic5, WallName::Floor);
    const auto left = engine::wallRectangle(ic5, WallName::Left);
    const auto ceiling = engine::wallRectangle(ic5, WallName::Ceiling);
    // The floor's top edge is the front wall's bottom edge; the left wall's right edge is the
    // front wall's left edge; the ceiling's bottom edge is the front wall's top edge.
    EXPECT_EQ(floor.topLeftM, front.topLeftM + front.heightM);
    EXPECT_EQ(floor.topLeftM + floor.widthM, front.topLeftM + front.heightM + front.widthM);
    EXPECT_EQ(left.topLeftM + left.widthM, front.topLeftM);
    EXPECT_EQ(ceiling.topLeftM + ceiling.heightM, front.topLeftM);
    EXPECT_NEAR(glm::length(front.widthM), 2.95, 1e-12);
    EXPECT_NEAR(glm::length(front.heightM), 2.21, 1e-12);
}

TEST(DisplayGeometry, PresetsValidateOrSayWhy) {
    EXPECT_NO_THROW(engine::validateDisplay(engine::displayPreset("ic5")));
    EXPECT_NO_THROW(engine::validateDisplay(engine::displayPreset("cave6")));
    // cave4 lacks the ceiling and the back: the map opens both onto its four walls.
    EXPECT_NO_THROW(engine::validateDisplay(engine::displayPreset("cave4")));
    EXPECT_EQ(engine::caveBoxOf(engine::displayPreset("cave4")).missingFaces,
              conformal::faceBit(conformal::kCeilingFace) | conformal::faceBit(4));
    engine::Display cave4 = engine::displayPreset("cave4");
    cave4.map = conformal::MapKind::None;
    EXPECT_NO_THROW(engine::validateDisplay(cave4));
    // Two opposite walls are not a disc: refused with the reason, naming the way out.
    engine::Display twoWalls = engine::displayPreset("cave4");
    twoWalls.walls = {{WallName::Left, 64, 64}, {WallName::Right, 64, 64}};
    try {
        engine::validateDisplay(twoWalls);
        FAIL() << "two opposite walls with a map should be refused";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("are in pieces"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("use map none"), std::string::npos) << e.what();
    }
    engine::Display noFloor = engine::displayPreset("cave4");
    noFloor.walls.pop_back();
    noFloor.map = conformal::MapKind::Linear;
    EXPECT_THROW(engine::validateDisplay(noFloor), std::invalid_argument);
    noFloor.map = conformal::MapKind::Conformal;
    EXPECT_NO_THROW(engine::validateDisplay(noFloor));
    EXPECT_THROW(engine::displayPreset("ic7"), std::invalid_argument);

    engine::Display bad = engine::displayPreset("ic5");
    bad.headPositionM = {0.0, 0.0, 5.0};
    EXPECT_THROW(engine::validateDisplay(bad), std::invalid_argument);
    bad = engine::displayPreset("ic5");
    bad.walls.push_back(bad.walls.front());
    EXPECT_THROW(engine::validateDisplay(bad), std::invalid_argument);
}

TEST(DisplayGeometry, PointOnAWallProjectsToItsPixel) {
    const engine::Display ic5 = engine::displayPreset("ic5");
    engine::ScenePose pose;
    pose.positionMm = {100.0, 120.0, 80.0};
    pose.forward = glm::normalize(glm::dvec3(0.3, 0.1, 1.0));
    pose.up = {0.0, -1.0, 0.0};
    pose.mmPerMetre = 15.0;
    const glm::dmat3 rotation = engine::caveToVolumeRotation(pose);
    EXPECT_NEAR(glm::determinant(rotation), 1.0, 1e-12);  // a proper rotation: right-handed
    for (WallName wall : {WallName::Front, WallName::Left, WallName::Floor}) {
        const auto rect = engine::wallRectangle(ic5, wall);
        const auto view = engine::wallView(ic5, wall, engine::Eye::Left, pose, engine::WarpMode::Chord);
        // A point 30 % across and 70 % down the wall, in CAVE metres, then in volume mm.
        const glm::dvec3 pointM = rect.topLeftM + 0.3 * rect.widthM + 0.7 * rect.heightM;
        const glm::dvec3 pointMm = pose.positionMm + rotation * pointM * pose.mmPerMetre;
        const double column = 0.3 * view.rays.width - 0.5;
        const double row = 0.7 * view.rays.height - 0.5;
        const glm::dvec3 expected = glm::normalize(pointMm - view.rays.eyeMm);
        EXPECT_NEAR(glm::length(engine::rayDirectionOf(view.rays, column, row) - expected), 0.0, 1e-12);
        EXPECT_EQ(view.warp.mode, engine::WarpMode::Chord);
    }
    // The left eye sits half the separation to the CAVE's left (-x) of the head.
    const auto left = engine::wallView(ic5, WallName::Front, engine::Eye::Left, pose, engine::WarpMode::Chord);
    const auto right = engine::wallView(ic5, WallName::Front, engine::Eye::Right, pose, engine::WarpMode::Chord);
    EXPECT_NEAR(glm::length(right.rays.eyeMm - left.rays.eyeMm), 0.065 * 15.0, 1e-9);
    EXPECT_GT(glm::dot(right.rays.eyeMm - left.rays.eyeMm, rotation[0]), 0.0);
}

TEST(DisplayGeometry, PoseCarriesTheMapCentreAndTheBoxSitsAroundIt) {
    // The rays bend about the map centre (the centre of the baked sphere of directions), so the
    // pose places that point; an off-centre map shifts the walls and eyes, not the bend.
    engine::Display ic5 = engine::displayPreset("ic5");
    ic5.mapCentreM = {0.1, -0.3, 0.2};
    engine::ScenePose pose;
    pose.positionMm = {100.0, 120.0, 80.0};
    pose.forward = glm::normalize(glm::dvec3(0.3, 0.1, 1.0));
    pose.up = {0.0, -1.0, 0.0};
    pose.mmPerMetre = 15.0;
    const glm::dmat3 rotation = engine::caveToVolumeRotation(pose);
    const auto view = engine::wallView(ic5, WallName::Front, engine::Eye::Left, pose, engine::WarpMode::Chord);
    EXPECT_EQ(view.warp.mapCentreMm, pose.positionMm);
    const auto rect = engine::wallRectangle(ic5, WallName::Front);
    const glm::dvec3 wallOriginMm = pose.positionMm + rotation * (rect.topLeftM - ic5.mapCentreM) * pose.mmPerMetre;
    EXPECT_NEAR(glm::length(view.rays.wallOriginMm - wallOriginMm), 0.0, 1e-9);
    const glm::dvec3 eyeMm =
        pose.positionMm + rotation * (engine::eyePositionM(ic5, engine::Eye::Left) - ic5.mapCentreM) * pose.mmPerMetre;
    EXPECT_NEAR(glm::length(view.rays.eyeMm - eyeMm), 0.0, 1e-9);
}

TEST(DisplayGeometry, MapCentreMustLieStrictlyInsideTheBox) {
    engine::Display display = engine::displayPreset("ic5");
    display.mapCentreM = {0.0, 0.5 * display.boxSizeM.y, 0.0};  // on the ceiling's plane
    try {
        engine::validateDisplay(display);
        FAIL() << "a map centre on the box's surface was accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("map centre (map_centre_m)"), std::string::npos) << e.what();
    }
    display.mapCentreM = {0.0, 0.49 * display.boxSizeM.y, 0.0};
    EXPECT_NO_THROW(engine::validateDisplay(display));
}

}  // namespace
