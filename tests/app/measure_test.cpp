// `cvc measure` as a user runs it on the colon phantom: polyps of 3 to 15 mm (sessile and
// pedunculated) rendered through a pinhole with --hits, their diameters measured from the
// pixel of the polyp's centre against the phantom's truth; the two-pixel distance against the
// hits themselves; one clear line for bad input.
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <vector>

#include <glm/glm.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/support/run_program.h"

namespace {

namespace fs = std::filesystem;
using testing_support::lineCount;
using testing_support::readWholeFile;
using testing_support::runCvc;

fs::path tmp(const std::string& name) { return fs::path(CVC_TEST_TMP_DIR) / "measure_cli" / name; }

glm::dvec3 vec(const nlohmann::json& v) { return {v[0].get<double>(), v[1].get<double>(), v[2].get<double>()}; }
std::string list(const glm::dvec3& v) {
    std::ostringstream out;
    out.precision(10);
    out << v.x << ',' << v.y << ',' << v.z;
    return out.str();
}

/// The phantom at 200^3 x 0.6 mm with polyps of 3 to 15 mm spread along the colon and around it.
const fs::path& phantom() {
    static const fs::path volume = [] {
        fs::create_directories(tmp(""));
        const fs::path path = testing_support::processTmp("measure_colon.nrrd");
        const auto run = runCvc("phantom --size 200 --spacing 0.6 --polyp sessile:3:0.2:30 --polyp sessile:6:0.38:150 "
                                "--polyp sessile:10:0.55:270 --polyp sessile:15:0.72:90 --polyp "
                                "pedunculated:8:0.88:210:1.5 --force -o " +
                                path.string());
        EXPECT_EQ(run.exitCode, 0) << run.err;
        return path;
    }();
    return volume;
}

struct Truth {
    nlohmann::json doc;
    std::vector<glm::dvec3> centreline;
    std::vector<double> arcMm;
    std::vector<double> foldArcMm;
    double lumenRadiusMm = 0.0, foldDepthMm = 0.0, foldHalfWidthMm = 0.0;
};

Truth readTruth() {
    Truth t;
    t.doc = nlohmann::json::parse(readWholeFile(fs::path(phantom()).replace_extension(".json")));
    double walked = 0.0;
    for (const auto& p : t.doc["centreline_mm"]) {
        if (!t.centreline.empty()) walked += glm::length(vec(p) - t.centreline.back());
        t.centreline.push_back(vec(p));
        t.arcMm.push_back(walked);
    }
    for (const auto& a : t.doc["fold_arc_lengths_mm"]) t.foldArcMm.push_back(a.get<double>());
    t.lumenRadiusMm = t.doc["lumen_radius_mm"].get<double>();
    t.foldDepthMm = t.doc["fold"]["depth_mm"].get<double>();
    t.foldHalfWidthMm = t.doc["fold"]["half_width_mm"].get<double>();
    return t;
}

/// Whether the segment from `eye` to where it meets the polyp (sphere `centre`, `radius`) stays
/// in the open lumen: inside the tube, and clear of the folds' ridges.
bool clearView(const Truth& t, const glm::dvec3& eye, const glm::dvec3& centre, double radius) {
    const glm::dvec3 entry = centre + radius * glm::normalize(eye - centre);
    for (int s = 0; s <= 200; ++s) {
        const glm::dvec3 p = eye + (entry - eye) * (s / 200.0);
        if (glm::length(p - centre) < radius + 1.5) continue;
        double best = 1e30, arc = 0.0;
        for (std::size_t i = 0; i < t.centreline.size(); ++i) {
            const double d = glm::length(p - t.centreline[i]);
            if (d < best) best = d, arc = t.arcMm[i];
        }
        double limit = t.lumenRadiusMm - 0.7;
        for (double fold : t.foldArcMm) {
            if (std::abs(arc - fold) < t.foldHalfWidthMm + 1.5) limit = t.lumenRadiusMm - t.foldDepthMm - 0.7;
        }
        if (best > limit) return false;
    }
    return true;
}

struct View {
    glm::dvec3 eye, centre, up;
    double fovDeg;
};

/// A centreline point about 2.5 diameters from the polyp with a clear view of it (the nearest
/// centreline point for the small ones, nearer than that), looking at its centre; the polyp spans
/// about a third of the image.
View viewOf(const Truth& t, const nlohmann::json& polyp) {
    const glm::dvec3 centre = vec(polyp["centre_mm"]);
    const double radius = polyp["radius_mm"].get<double>(), diameter = 2.0 * radius;
    double nearest = 1e30;
    for (const auto& p : t.centreline) nearest = std::min(nearest, glm::length(p - centre));
    const double want = std::max(2.5 * diameter, nearest);
    double bestScore = 1e30;
    View view{};
    for (const auto& p : t.centreline) {
        const double distance = glm::length(p - centre);
        if (distance > 3.5 * diameter && distance > nearest + 0.01) continue;
        const double score = std::abs(distance - want);
        if (score >= bestScore || !clearView(t, p, centre, radius)) continue;
        bestScore = score;
        view.eye = p;
    }
    EXPECT_LT(bestScore, 1e29) << "no clear view of the " << diameter << " mm polyp";
    view.centre = centre;
    const glm::dvec3 forward = glm::normalize(centre - view.eye);
    const int axis = std::abs(forward.x) < std::abs(forward.y) ? (std::abs(forward.x) < std::abs(forward.z) ? 0 : 2)
                                                               : (std::abs(forward.y) < std::abs(forward.z) ? 1 : 2);
    view.up = glm::dvec3(0.0);
    view.up[axis] = 1.0;
    view.fovDeg = glm::degrees(3.0 * 2.0 * std::atan(radius / glm::length(centre - view.eye)));
    return view;
}

fs::path renderHits(const View& view, const std::string& name) {
    const fs::path hits = tmp(name + ".nrrd");
    const auto run = runCvc("render " + phantom().string() + " --position " + list(view.eye) + " --look-at " +
                            list(view.centre) + " --up " + list(view.up) + " --fov " + std::to_string(view.fovDeg) +
                            " --size 512x512 --hits " + hits.string() + " -o " + tmp(name + ".png").string() +
                            " --force");
    EXPECT_EQ(run.exitCode, 0) << run.err;
    return hits;
}

/// The 4-vector hit image of a pinhole render, as floats (x, y, z, w per pixel).
std::vector<float> readRawHits(const fs::path& path, int& width, int& height) {
    const std::string bytes = readWholeFile(path);
    const std::size_t end = bytes.find("\n\n");
    const std::size_t sizes = bytes.find("sizes: 4 ");
    EXPECT_NE(end, std::string::npos);
    EXPECT_NE(sizes, std::string::npos);
    std::istringstream(bytes.substr(sizes + 9)) >> width >> height;
    std::vector<float> values(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 4);
    EXPECT_EQ(bytes.size() - end - 2, values.size() * 4);
    std::memcpy(values.data(), bytes.data() + end + 2, values.size() * 4);
    return values;
}

TEST(CvcMeasure, PolypDiametersOnThePhantomMatchTheTruth) {
    const Truth truth = readTruth();
    ASSERT_EQ(truth.doc["polyps"].size(), 5u);
    const double voxelMm = truth.doc["spacing_mm"][0].get<double>();
    int index = 0;
    for (const auto& polyp : truth.doc["polyps"]) {
        const std::string name = "polyp" + std::to_string(index++);
        const View view = viewOf(truth, polyp);
        const fs::path hits = renderHits(view, name);
        const fs::path json = tmp(name + ".json");
        fs::remove(json);
        // The polyp's centre projects to the image centre: it lies between pixels 255 and 256.
        const auto run = runCvc("measure " + hits.string() + " --polyp-diameter 256,256 --json " + json.string());
        ASSERT_EQ(run.exitCode, 0) << run.err;
        const auto summary = nlohmann::json::parse(readWholeFile(json));
        const double truthMm = polyp["diameter_mm"].get<double>();
        const double measured = summary["diameter_mm"].get<double>();
        const glm::dvec3 seedHit = vec(summary["seed"]["hit_mm"]);
        std::cout << "  " << polyp["kind"].get<std::string>() << " " << truthMm << " mm seen from "
                  << glm::length(view.eye - view.centre) << " mm, "
                  << glm::degrees(std::acos(glm::dot(glm::normalize(view.eye - view.centre), vec(polyp["base_normal"]))))
                  << " deg off its base normal: measured " << measured << " mm (" << summary["pixel_count"]
                  << " pixels)\n";
        EXPECT_NEAR(glm::length(seedHit - view.centre), polyp["radius_mm"].get<double>(), 1.0)
            << name << ": the seed is on the polyp";
        EXPECT_NEAR(measured, truthMm, voxelMm) << name << " " << run.out;
        EXPECT_NE(run.out.find("polyp diameter: "), std::string::npos) << run.out;
    }
}

TEST(CvcMeasure, DistanceBetweenTwoPixelsIsTheirHitsDistance) {
    const Truth truth = readTruth();
    const View view = viewOf(truth, truth.doc["polyps"][1]);
    const fs::path hits = renderHits(view, "distance");
    int width = 0, height = 0;
    const std::vector<float> raw = readRawHits(hits, width, height);
    ASSERT_EQ(width, 512);
    auto at = [&](int x, int y) {
        const std::size_t i = (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)) * 4;
        EXPECT_GT(raw[i + 3], 0.0f) << "pixel " << x << "," << y << " is a hit";
        return glm::dvec3(raw[i], raw[i + 1], raw[i + 2]);
    };
    const double expected = glm::length(at(100, 300) - at(400, 200));
    const fs::path json = tmp("distance.json");
    fs::remove(json);
    const auto run = runCvc("measure " + hits.string() + " --from 100,300 --to 400,200 --json " + json.string());
    ASSERT_EQ(run.exitCode, 0) << run.err;
    EXPECT_EQ(run.out.rfind("distance: ", 0), 0u) << run.out;
    EXPECT_NE(run.out.find(" mm between (100,300) at ("), std::string::npos) << run.out;
    const auto summary = nlohmann::json::parse(readWholeFile(json));
    EXPECT_NEAR(summary["distance_mm"].get<double>(), expected, 1e-4);
    EXPECT_GT(expected, 1.0);

    // --json is not replaced without --force.
    const auto again = runCvc("measure " + hits.string() + " --from 100,300 --to 400,200 --json " + json.string());
    EXPECT_EQ(again.exitCode, 1);
    EXPECT_NE(again.err.find("exists"), std::string::npos) << again.err;
    EXPECT_EQ(runCvc("measure " + hits.string() + " --from 1,1 --to 2,2 --json " + json.string() + " --force").exitCode, 0);
}

TEST(CvcMeasure, BadInputGetsOneClearLine) {
    const Truth truth = readTruth();
    const View view = viewOf(truth, truth.doc["polyps"][0]);
    const fs::path hits = renderHits(view, "bad");
    auto expectOneLine = [](const testing_support::ProgramRun& run, const std::string& words) {
        EXPECT_EQ(run.exitCode, 1) << run.err;
        EXPECT_EQ(run.err.rfind("cvc: error: ", 0), 0u) << run.err;
        EXPECT_NE(run.err.find(words), std::string::npos) << run.err;
        EXPECT_EQ(lineCount(run.err), 1) << run.err;
        EXPECT_TRUE(run.out.empty()) << run.out;
    };
    expectOneLine(runCvc("measure " + tmp("missing.nrrd").string() + " --polyp-diameter 1,1"), "cannot be read");
    expectOneLine(runCvc("measure " + hits.string() + " --from 1,1 --to 2,2 --polyp-diameter 3,3"), "not both");
    expectOneLine(runCvc("measure " + hits.string()), "not neither");
    expectOneLine(runCvc("measure " + hits.string() + " --from 1,1"), "--from and --to go together");
    expectOneLine(runCvc("measure " + hits.string() + " --polyp-diameter 600,3"), "outside the 512x512 hit image");
    expectOneLine(runCvc("measure " + hits.string() + " --polyp-diameter 1x2"), "expected a pixel X,Y");
    std::ofstream(tmp("text.nrrd")) << "hello\n";
    expectOneLine(runCvc("measure " + tmp("text.nrrd").string() + " --polyp-diameter 1,1"), "not a hit image");
    // A miss: a pinhole render from outside the volume looking away from it.
    const fs::path away = tmp("away.nrrd");
    ASSERT_EQ(runCvc("render " + phantom().string() + " --position -50,-50,-50 --look-at -100,-100,-100 --up 0,0,1 "
                     "--fov 30 --size 16x16 --hits " + away.string() + " -o " + tmp("away.png").string() + " --force")
                  .exitCode,
              0);
    expectOneLine(runCvc("measure " + away.string() + " --from 3,3 --to 4,4"), "pixel (3, 3) is a miss");
}

}  // namespace
