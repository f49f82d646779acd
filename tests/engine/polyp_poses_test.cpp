// polyp-check's poses from a display's own walls: for the cabin the sweep runs up over the missing
// ceiling (wall 15 degrees up, edge 28, ceiling_44/50/60, a corner pose on the ceiling 5 degrees
// past its front corner, at 33 degrees up and 45 across); for cave4 it runs on over the head to
// the missing back, with poses behind and above-behind off the plane where its slit's spine
// runs; the singular points are the missing walls' boundary corners and edge midpoints; a pose
// turns the view so that the polyp lies along its direction.
#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

#include <gtest/gtest.h>

#include "conformal/cave_box.h"
#include "engine/display/display.h"
#include "engine/studies/polyp_poses.h"

namespace {

std::map<std::string, glm::dvec3> posesByName(const engine::Display& display) {
    std::map<std::string, glm::dvec3> poses;
    for (const auto& pose : engine::polypPosesFor(display)) poses[pose.name] = pose.directionCave;
    return poses;
}

TEST(PolypPoses, CabinSweepsUpOverItsMissingCeiling) {
    const engine::Display cabin = engine::displayPreset("ic5");
    const auto poses = posesByName(cabin);
    // The ceiling's front edge is 36.85 degrees up seen from the cabin's centre (1.105 / 1.475 m).
    const double edge = glm::degrees(std::atan2(0.5 * 2.21, 0.5 * 2.95));
    const auto elevationOf = [&](const std::string& name) { return engine::elevationAzimuthDegOf(poses.at(name)).x; };
    EXPECT_NEAR(elevationOf("wall"), 15.0, 1e-6);
    EXPECT_NEAR(elevationOf("edge"), edge - 9.0, 0.06);
    EXPECT_NEAR(elevationOf("ceiling_44"), edge + 7.0, 0.06);
    EXPECT_NEAR(elevationOf("ceiling_50"), edge + 13.0, 0.06);
    EXPECT_NEAR(elevationOf("ceiling_60"), edge + 23.0, 0.06);
    EXPECT_NEAR(engine::elevationAzimuthDegOf(poses.at("ceiling_90")).x, 90.0, 0.1);  // the zenith
    ASSERT_TRUE(poses.count("ceiling_117") && poses.count("ceiling_90_side") && poses.count("ceiling_117_side"));
    for (const auto& [name, direction] : poses) {
        const bool isOnCeiling = name.rfind("ceiling_", 0) == 0 || name == "corner";
        EXPECT_EQ(engine::missingWallOf(cabin, direction), isOnCeiling ? "ceiling" : "") << name;
        EXPECT_NEAR(glm::length(direction), 1.0, 1e-12) << name;
    }
    // The corner pose: 5 degrees past the ceiling's front-right (or left) corner, toward the zenith.
    const glm::dvec2 corner = engine::elevationAzimuthDegOf(poses.at("corner"));
    EXPECT_NEAR(corner.x, 27.9 + 5.0, 0.2);
    EXPECT_NEAR(std::abs(corner.y), 45.0, 0.01);  // the sweep's plane from a sampled mean of the missing directions
    // Its singular points: the ceiling's four corners and four edge midpoints.
    const auto singular = engine::singularDirectionsOf(cabin);
    EXPECT_EQ(singular.size(), 8u);
    EXPECT_NEAR(engine::singularDistanceDeg(singular, glm::dvec3(0.0, std::sin(glm::radians(edge)), -std::cos(glm::radians(edge)))),
                0.0, 1e-6);
    EXPECT_NEAR(engine::singularDistanceDeg(singular, engine::caveDirectionOf(15.0, 0.0)), edge - 15.0, 1e-6);
}

TEST(PolypPoses, Cave4LooksBehindAndAboveBehindOffItsSpine) {
    const engine::Display cave = engine::displayPreset("cave4");
    const auto poses = posesByName(cave);
    // Missing ceiling and back of a cube: the sweep meets the ceiling 45 degrees up and leaves the
    // back 45 degrees below the horizon behind, so its middle is above-behind, its three quarters
    // straight behind.
    ASSERT_TRUE(poses.count("ceiling_135_side") || poses.count("back_135_side"));
    ASSERT_TRUE(poses.count("back_180_side"));
    const glm::dvec3 behind = poses.at("back_180_side");
    EXPECT_GT(behind.z, 0.8);                    // behind the viewer
    EXPECT_NEAR(std::abs(behind.x), 0.5, 1e-4);  // 30 degrees off the mirror plane
    const glm::dvec3 aboveBehind = poses.count("ceiling_135_side") ? poses.at("ceiling_135_side") : poses.at("back_135_side");
    EXPECT_GT(aboveBehind.y, 0.6);
    EXPECT_GT(aboveBehind.z, 0.6);
    for (const auto& [name, direction] : poses) {
        if (name == "wall" || name == "edge") {
            EXPECT_EQ(engine::missingWallOf(cave, direction), "") << name;
        } else if (name != "corner") {
            EXPECT_NE(engine::missingWallOf(cave, direction), "") << name;
        }
    }
    EXPECT_NEAR(engine::elevationAzimuthDegOf(poses.at("edge")).x, 36.0, 0.06);  // the front edge at 45
    // Six corners (four slit tips and the two convex back-top corners) and six edge midpoints.
    EXPECT_EQ(engine::singularDirectionsOf(cave).size(), 12u);
}

TEST(PolypPoses, PoseSeeingPutsThePointAlongThePoseDirection) {
    engine::CameraPose base;
    base.positionMm = {10.0, 20.0, 30.0};
    base.forward = glm::normalize(glm::dvec3(0.3, -0.2, 1.0));
    base.up = glm::normalize(glm::cross(glm::cross(base.forward, glm::dvec3(0.0, 1.0, 0.0)), base.forward));
    const glm::dvec3 point(25.0, 31.0, 70.0);
    for (const glm::dvec3& direction : {engine::caveDirectionOf(50.0, 0.0), engine::caveDirectionOf(33.0, 45.0),
                                        glm::normalize(glm::dvec3(0.5, 0.3, 0.8))}) {
        const engine::CameraPose pose = engine::poseSeeing(base, point, direction);
        engine::ScenePose scene{pose.positionMm, pose.forward, pose.up, 10.0};
        const glm::dvec3 inCave = glm::transpose(engine::caveToVolumeRotation(scene)) * glm::normalize(point - pose.positionMm);
        EXPECT_LT(glm::length(inCave - direction), 1e-9);
        EXPECT_LT(glm::length(pose.positionMm - base.positionMm), 1e-12);
    }
    EXPECT_THROW(engine::poseSeeing(base, base.positionMm, engine::caveDirectionOf(15.0, 0.0)), std::invalid_argument);
    // Elevation and azimuth round-trip through a CAVE direction.
    const glm::dvec2 back = engine::elevationAzimuthDegOf(engine::caveDirectionOf(20.0, -70.0));
    EXPECT_NEAR(back.x, 20.0, 1e-9);
    EXPECT_NEAR(back.y, -70.0, 1e-9);
}

TEST(PolypPoses, RefusesADisplayWithoutAMissingWallOrFront) {
    EXPECT_THROW(engine::polypPosesFor(engine::displayPreset("cave6")), std::invalid_argument);
    engine::Display noFront = engine::displayPreset("ic6");
    noFront.walls.erase(std::remove_if(noFront.walls.begin(), noFront.walls.end(),
                                       [](const engine::DisplayWall& w) { return w.name == engine::WallName::Front; }),
                        noFront.walls.end());
    EXPECT_THROW(engine::polypPosesFor(noFront), std::invalid_argument);
}

}  // namespace
