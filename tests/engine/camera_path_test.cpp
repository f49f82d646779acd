// Camera poses along a centreline: positions on the path at the asked spacing, views along
// its tangent, a rotation-minimizing up, both directions, and the files paths come from.
#include <cmath>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "engine/sequence/camera_path.h"

namespace {

constexpr double kPi = 3.14159265358979323846;

/// A helix of radius 20 mm and pitch 30 mm per turn, sampled every 0.1 radian.
std::vector<glm::dvec3> helix(int samples = 400) {
    std::vector<glm::dvec3> points;
    for (int i = 0; i < samples; ++i) {
        const double a = 0.1 * i;
        points.emplace_back(50.0 + 20.0 * std::cos(a), 50.0 + 20.0 * std::sin(a), 10.0 + 30.0 * a / (2.0 * kPi));
    }
    return points;
}

glm::dvec3 helixTangent(double angle) {
    return glm::normalize(glm::dvec3(-20.0 * std::sin(angle), 20.0 * std::cos(angle), 30.0 / (2.0 * kPi)));
}

/// Distance from p to the nearest segment of the polyline.
double distanceToPolyline(const std::vector<glm::dvec3>& line, const glm::dvec3& p) {
    double best = 1e300;
    for (std::size_t i = 1; i < line.size(); ++i) {
        const glm::dvec3 a = line[i - 1], b = line[i];
        const double f = std::clamp(glm::dot(p - a, b - a) / glm::dot(b - a, b - a), 0.0, 1.0);
        best = std::min(best, glm::length(p - (a + f * (b - a))));
    }
    return best;
}

TEST(CameraPath, PosesFollowTheCentreline) {
    const auto line = helix();
    engine::PathSettings settings;
    settings.stepMm = 2.0;
    settings.smoothingMm = 2.0;
    const auto poses = engine::posesAlong(line, settings);
    ASSERT_GT(poses.size(), 100u);
    for (std::size_t i = 0; i < poses.size(); ++i) {
        const auto& pose = poses[i];
        EXPECT_LT(distanceToPolyline(line, pose.positionMm), 1e-9);
        EXPECT_NEAR(glm::length(pose.forward), 1.0, 1e-12);
        EXPECT_NEAR(glm::length(pose.up), 1.0, 1e-12);
        EXPECT_NEAR(glm::dot(pose.forward, pose.up), 0.0, 1e-9);
        if (i > 0) {
            // Consecutive poses are one step apart along the arc (the chord is a bit shorter).
            const double chord = glm::length(pose.positionMm - poses[i - 1].positionMm);
            EXPECT_GT(chord, 1.99);
            EXPECT_LE(chord, 2.0 + 1e-9);
            EXPECT_GT(glm::dot(pose.up, poses[i - 1].up), 0.99) << "up must not flip or spin at pose " << i;
        }
        // Away from the ends, the view looks along the helix's analytic tangent.
        if (i > 5 && i + 5 < poses.size()) {
            const double angle = (pose.positionMm.z - 10.0) * 2.0 * kPi / 30.0;  // z rises linearly with the angle
            EXPECT_GT(glm::dot(pose.forward, helixTangent(angle)), 0.999) << "pose " << i;
        }
    }
}

TEST(CameraPath, AntegradeAndRetrogradeAreMirrorImages) {
    // A polyline whose length is a whole number of steps: both directions visit the same points.
    const std::vector<glm::dvec3> line = {{0, 0, 0}, {30, 0, 0}, {30, 40, 0}, {30, 40, 30}};  // 100 mm
    engine::PathSettings settings;
    settings.stepMm = 5.0;
    settings.smoothingMm = 4.0;
    const auto forward = engine::posesAlong(line, settings);
    settings.direction = engine::Direction::Retrograde;
    const auto backward = engine::posesAlong(line, settings);
    ASSERT_EQ(forward.size(), 21u);
    ASSERT_EQ(backward.size(), forward.size());
    for (std::size_t i = 0; i < forward.size(); ++i) {
        const auto& a = forward[i];
        const auto& b = backward[forward.size() - 1 - i];
        EXPECT_LT(glm::length(a.positionMm - b.positionMm), 1e-9) << i;
        EXPECT_LT(glm::length(a.forward + b.forward), 1e-9) << i;  // opposite views at the same place
    }
}

TEST(CameraPath, PoseViewingAPointSeesItAtTheAskedElevation) {
    const std::vector<glm::dvec3> line = {{0, 0, 0}, {0, 0, 100}};
    const glm::dvec3 polyp(11.0, 0.0, 50.0);  // on the wall of a straight 22 mm colon
    engine::PathSettings settings;
    for (double elevation : {90.0, 60.0, 45.0}) {
        const auto pose = engine::poseViewing(line, polyp, elevation, settings);
        const glm::dvec3 toPolyp = glm::normalize(polyp - pose.positionMm);
        const double seen = glm::degrees(std::asin(glm::dot(toPolyp, pose.up)));
        EXPECT_NEAR(seen, elevation, 0.5);
        EXPECT_GE(glm::dot(toPolyp, pose.forward), -1e-9);  // ahead, never behind
        EXPECT_NEAR(glm::dot(pose.forward, pose.up), 0.0, 1e-9);
        EXPECT_NEAR(glm::dot(pose.forward, glm::dvec3(0, 0, 1)), 1.0, 1e-9);  // still looking along the path
    }
    EXPECT_THROW(engine::poseViewing(line, polyp, 0.0, settings), std::invalid_argument);
    EXPECT_THROW(engine::poseViewing(line, polyp, 180.0, settings), std::invalid_argument);
}

TEST(CameraPath, PoseViewingAPointBehindAndToTheSideSeesItThere) {
    const std::vector<glm::dvec3> line = {{0, 0, 0}, {0, 0, 100}};
    const glm::dvec3 polyp(11.0, 0.0, 50.0);
    engine::PathSettings settings;
    for (const double elevation : {120.0, 150.0}) {
        for (const double azimuth : {0.0, 45.0, -30.0}) {
            const auto pose = engine::poseViewing(line, polyp, elevation, settings, azimuth);
            const glm::dvec3 toPolyp = glm::normalize(polyp - pose.positionMm);
            // Past 90 degrees the point is behind: the pose is past it along the path.
            EXPECT_NEAR(glm::degrees(std::acos(glm::dot(toPolyp, pose.forward))), elevation, 0.5);
            EXPECT_GT(pose.positionMm.z, polyp.z);
            // Around the view axis it sits `azimuth` degrees right of up (right = forward x up).
            const glm::dvec3 across = glm::normalize(toPolyp - glm::dot(toPolyp, pose.forward) * pose.forward);
            const glm::dvec3 right = glm::cross(pose.forward, pose.up);
            EXPECT_NEAR(glm::degrees(std::atan2(glm::dot(across, right), glm::dot(across, pose.up))), azimuth, 1e-6);
            EXPECT_NEAR(glm::dot(pose.forward, pose.up), 0.0, 1e-9);
        }
    }
    EXPECT_THROW(engine::poseViewing(line, polyp, 150.0, settings, 200.0), std::invalid_argument);
}

TEST(CameraPath, ReadsTextAndPhantomJsonAndRejectsBadFiles) {
    const auto dir = std::filesystem::path(CVC_TEST_TMP_DIR);
    const auto text = dir / "path.txt";
    std::ofstream(text) << "# x y z\n0 0 0\n10, 0, 0\n\n10 10 0  # corner\n";
    EXPECT_EQ(engine::readPolyline(text.string()).size(), 3u);

    const auto json = dir / "truth.json";
    std::ofstream(json) << R"({"centreline_mm": [[0,0,0],[0,0,5],[0,5,5]], "polyps": [{"centre_mm": [1,2,3]}]})";
    EXPECT_EQ(engine::readPolyline(json.string()).size(), 3u);
    ASSERT_EQ(engine::readPolypCentres(json.string()).size(), 1u);
    EXPECT_EQ(engine::readPolypCentres(json.string())[0], glm::dvec3(1, 2, 3));

    const auto bad = dir / "bad_path.txt";
    std::ofstream(bad) << "0 0 0\n1 2\n";
    try {
        engine::readPolyline(bad.string());
        FAIL() << "a line of two numbers must be rejected";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("bad_path.txt:2"), std::string::npos) << e.what();
    }
    const auto single = dir / "single_point.txt";
    std::ofstream(single) << "1 1 1\n1 1 1\n";
    EXPECT_THROW(engine::readPolyline(single.string()), std::runtime_error);
    EXPECT_THROW(engine::readPolyline((dir / "missing.txt").string()), std::runtime_error);
    const auto nan = dir / "nan_path.txt";
    std::ofstream(nan) << "0 0 0\nnan 1 1\n";
    EXPECT_THROW(engine::readPolyline(nan.string()), std::runtime_error);

    engine::PathSettings tooMany;
    tooMany.stepMm = 1e-3;
    tooMany.maxFrames = 1000;
    EXPECT_THROW(engine::posesAlong(helix(), tooMany), std::invalid_argument);
}

TEST(CameraPath, SegmentsAndTheirOrderFromTextAndJson) {
    const auto dir = std::filesystem::path(CVC_TEST_TMP_DIR);
    // Text: "# segment N" starts a segment; the file runs rectum -> caecum as written.
    const auto text = dir / "segments.txt";
    std::ofstream(text) << "# segment 1\n0 0 0\n0 0 10\n0 0 20\n# segment 2\n0 30 20\n0 30 40\n";
    const auto fromText = engine::readCentreline(text.string());
    ASSERT_EQ(fromText.segments.size(), 2u);
    EXPECT_EQ(fromText.segments[0].front(), glm::dvec3(0, 0, 0));
    EXPECT_EQ(fromText.segments[1].back(), glm::dvec3(0, 30, 40));
    EXPECT_FALSE(fromText.anterior.has_value());

    // JSON: a phantom's truth runs caecum -> rectum and is turned round; segment_starts split it.
    const auto json = dir / "segments.json";
    std::ofstream(json) << R"({"centreline_mm": [[0,0,0],[0,0,10],[0,0,20],[0,30,20],[0,30,40]],
        "segment_starts": [0, 3], "centreline_order": "caecum_to_rectum", "anterior": [0, -2, 0]})";
    const auto fromJson = engine::readCentreline(json.string());
    ASSERT_EQ(fromJson.segments.size(), 2u);
    EXPECT_EQ(fromJson.segments[0].front(), glm::dvec3(0, 30, 40)) << "the rectal end comes first";
    EXPECT_EQ(fromJson.segments[1].back(), glm::dvec3(0, 0, 0));
    ASSERT_TRUE(fromJson.anterior.has_value());
    EXPECT_EQ(*fromJson.anterior, glm::dvec3(0, -1, 0));

    // Poses step along each segment and jump the gap: none lies between the segments.
    engine::PathSettings settings;
    settings.stepMm = 5.0;
    settings.smoothingMm = 2.0;
    const auto poses = engine::posesAlongSegments(fromText, settings);
    ASSERT_EQ(poses.size(), 5u + 5u);
    for (const auto& pose : poses) {
        const bool onFirst = pose.positionMm.y == 0.0 && pose.positionMm.z <= 20.0;
        const bool onSecond = std::abs(pose.positionMm.y - 30.0) < 1e-9 && pose.positionMm.z >= 20.0;
        EXPECT_TRUE(onFirst || onSecond) << pose.positionMm.y << " " << pose.positionMm.z;
        EXPECT_NEAR(glm::dot(pose.forward, pose.up), 0.0, 1e-9);
    }
    EXPECT_EQ(poses[5].positionMm, glm::dvec3(0, 30, 20));
    settings.direction = engine::Direction::Retrograde;
    const auto backward = engine::posesAlongSegments(fromText, settings);
    EXPECT_EQ(backward.front().positionMm, glm::dvec3(0, 30, 40));
    EXPECT_EQ(backward.back().positionMm, glm::dvec3(0, 0, 0));

    const auto badOrder = dir / "bad_order.json";
    std::ofstream(badOrder) << R"({"centreline_mm": [[0,0,0],[0,0,10]], "centreline_order": "up"})";
    EXPECT_THROW(engine::readCentreline(badOrder.string()), std::runtime_error);
    const auto badStarts = dir / "bad_starts.json";
    std::ofstream(badStarts) << R"({"centreline_mm": [[0,0,0],[0,0,10],[0,0,20]], "segment_starts": [0, 2]})";
    EXPECT_THROW(engine::readCentreline(badStarts.string()), std::runtime_error) << "a segment of one point";
}

TEST(CameraPath, AbsurdLengthsAreRefusedInOneLine) {
    // Found by fuzzing: a path 1e36 mm long has more frames than any integer holds, and one
    // from -1e308 to 1e308 an infinite length; both are refused with a message, never cast.
    engine::PathSettings settings;
    try {
        engine::posesAlong({{0, 0, 0}, {0, 0, 1e36}}, settings);
        FAIL() << "a path of 1e36 mm must be refused";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("5e+35 frames exceed the limit"), std::string::npos) << e.what();
    }
    try {
        engine::posesAlong({{-1e308, 0, 0}, {1e308, 0, 0}}, settings);
        FAIL() << "a path of infinite length must be refused";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("length overflows"), std::string::npos) << e.what();
    }
}

}  // namespace
