// `cvc polyp-check` on the colon phantom: the polyps of 6 mm and more keep their shape through
// the conformal map at the wall, edge and ceiling poses for both eyes (aspect and circularity
// within 3 % of the pinhole reference, the painted grid within 2 degrees), the linear baseline
// does not, and without a map the polyps on the ceiling's directions are cut off.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/support/run_program.h"

namespace {

namespace fs = std::filesystem;
using testing_support::readWholeFile;
using testing_support::runCvc;

fs::path tmp(const std::string& name) { return fs::path(CVC_TEST_TMP_DIR) / name; }

TEST(CvcPolypCheck, ConformalKeepsPolypShapesWhereTheLinearMapLosesThem) {
    fs::create_directories(tmp("polyp_check"));
    const fs::path volume = tmp("polyp_check/colon.nrrd"), truth = tmp("polyp_check/colon.json");
    ASSERT_EQ(runCvc("phantom --force -o " + volume.string()).exitCode, 0);
    const fs::path out = tmp("polyp_check/out");
    fs::remove_all(out);
    // Walls at half the cabin's density keep the test short; the polyps stay 25+ pixels across.
    const auto run = runCvc("polyp-check " + volume.string() + " --truth " + truth.string() +
                            " --polyps 0,1,3,4 --wall-size 700x525 -o " + out.string());
    ASSERT_EQ(run.exitCode, 0) << run.err;
    EXPECT_TRUE(fs::exists(out / "polyp_check.md"));
    EXPECT_TRUE(fs::exists(out / "crops" / "polyp_3_ceiling_50_left.png"));
    const auto doc = nlohmann::json::parse(readWholeFile(out / "polyp_check.json"));

    std::set<std::string> targetedPoses;
    int checked = 0;
    for (const auto& r : doc["results"]) {
        const std::string where = r["pose"].get<std::string>() + " polyp " + std::to_string(r["polyp"].get<int>()) + " " +
                                  r["eye"].get<std::string>() + " " + r["map"].get<std::string>();
        if (!r["targeted"].get<bool>()) continue;
        targetedPoses.insert(r["pose"].get<std::string>());
        if (r["map"] == "conformal") {
            ASSERT_TRUE(r["visible"].get<bool>()) << where;
            EXPECT_GE(r["pixels_across"].get<double>(), 25.0) << where;
            EXPECT_GE(r["singular_distance_deg"].get<double>(), 10.0) << where;
            EXPECT_LT(r["aspect_error"].get<double>(), 0.03) << where;
            EXPECT_LT(r["circularity_error"].get<double>(), 0.03) << where;
            EXPECT_LT(r["grid_angle_error_deg"].get<double>(), 2.0) << where;
            ++checked;
        }
        if (r["map"] == "none" && r["on_ceiling"].get<bool>()) {
            EXPECT_FALSE(r["visible"].get<bool>()) << where << ": the ceiling is missing";
        }
    }
    EXPECT_EQ(checked, 4 * 4 * 2);  // polyps x targeted poses x eyes
    EXPECT_EQ(targetedPoses, (std::set<std::string>{"wall", "edge", "ceiling_44", "ceiling_50"}));
    // On the ceiling's directions the linear baseline is far from the reference.
    const double conformal = doc["worst_aspect_error"]["conformal"].get<double>();
    const double linear = doc["worst_aspect_error"]["linear"].get<double>();
    EXPECT_LT(conformal, 0.03);
    EXPECT_GT(linear, 0.3);
    EXPECT_GT(linear, 10.0 * conformal);

    const auto again = runCvc("polyp-check " + volume.string() + " --truth " + truth.string() + " --polyps 0 -o " +
                              out.string());
    EXPECT_EQ(again.exitCode, 1);
    EXPECT_NE(again.err.find("use --force"), std::string::npos) << again.err;
}

TEST(CvcPolypCheck, BadInputGetsOneClearLine) {
    fs::create_directories(tmp("polyp_check_bad"));
    const fs::path volume = testing_support::processTmp("polyp_check_bad.nrrd");
    const fs::path truth = fs::path(volume).replace_extension(".json");
    ASSERT_EQ(runCvc("phantom --size 112 --spacing 1.4 --force -o " + volume.string()).exitCode, 0);
    const auto expectOneLine = [](const testing_support::ProgramRun& run, const std::string& words) {
        EXPECT_EQ(run.exitCode, 1) << run.err;
        EXPECT_NE(run.err.find("cvc: error: "), std::string::npos) << run.err;
        EXPECT_NE(run.err.find(words), std::string::npos) << run.err;
        EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
    };
    const std::string base = "polyp-check " + volume.string() + " -o " + tmp("polyp_check_bad/out").string();
    expectOneLine(runCvc(base + " --truth " + tmp("polyp_check_bad/missing.json").string()), "cannot open the ground truth");
    expectOneLine(runCvc(base + " --truth " + truth.string() + " --display cave6"), "has no map to check");
    expectOneLine(runCvc(base + " --truth " + truth.string() + " --polyps 9 --wall-size 64x48"),
                  "polyp 9: the ground truth lists 5 polyps");
    expectOneLine(runCvc(base + " --truth " + truth.string() + " --wall-size big"), "big");
    // A truth without a centreline has nowhere to stand the eye.
    std::ofstream(tmp("polyp_check_bad/no_path.json")) << R"({"polyps": [{"kind": "sessile", "diameter_mm": 6,
        "centre_mm": [1, 2, 3], "base_mm": [1, 2, 3], "base_normal": [0, 0, 1]}]})";
    expectOneLine(runCvc(base + " --truth " + tmp("polyp_check_bad/no_path.json").string()), "centreline_mm");
}

}  // namespace
