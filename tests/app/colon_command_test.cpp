// `cvc colon` as a user runs it: the files it writes, refusing to overwrite, one clear line for
// a scan without a colon; and `cvc render --path auto` flying through the analysis it runs.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/support/run_program.h"

namespace {

namespace fs = std::filesystem;
using testing_support::readWholeFile;
using testing_support::runCvc;

fs::path tmp(const std::string& name) { return fs::path(CVC_TEST_TMP_DIR) / name; }

/// The anatomy phantom at a coarse grid (a collapse, a fluid pool, body and lungs), made once.
const fs::path& anatomyPhantom() {
    static const fs::path volume = [] {
        fs::create_directories(tmp("colon_cli"));
        const fs::path path = testing_support::processTmp("colon_cli_anatomy.nrrd");
        const auto run = runCvc("phantom --anatomy --size 128 --spacing 1.2 --force -o " + path.string());
        EXPECT_EQ(run.exitCode, 0) << run.err;
        return path;
    }();
    return volume;
}

TEST(CvcColon, WritesLabelsCentrelineReportAndOverview) {
    const fs::path out = tmp("colon_cli/analysis");
    fs::remove_all(out);
    const fs::path summary = tmp("colon_cli/summary.json");
    fs::remove(summary);
    const auto run = runCvc("colon " + anatomyPhantom().string() + " -o " + out.string() + " --json " + summary.string());
    ASSERT_EQ(run.exitCode, 0) << run.err;
    for (const char* name : {"lumen.nrrd", "centreline.txt", "colon.json", "overview.png", "cleansed.nrrd"}) {
        EXPECT_TRUE(fs::exists(out / name)) << name;
    }
    EXPECT_NE(run.out.find("2 segment(s), rectum -> caecum"), std::string::npos) << run.out;
    EXPECT_NE(run.out.find("cleansed 1 pool(s)"), std::string::npos) << run.out;
    EXPECT_NE(run.err.find("[2/4] extracting centrelines"), std::string::npos) << run.err;
    const std::string text = readWholeFile(out / "centreline.txt");
    EXPECT_NE(text.find("# segment 1\n"), std::string::npos);
    EXPECT_NE(text.find("# segment 2\n"), std::string::npos);
    const auto report = nlohmann::json::parse(readWholeFile(out / "colon.json"));
    EXPECT_EQ(report["centreline_order"], "rectum_to_caecum");
    EXPECT_EQ(report["segments"].size(), 2u);
    EXPECT_EQ(report["gaps_mm"].size(), 1u);
    EXPECT_EQ(report["segment_starts"].size(), 2u);
    EXPECT_TRUE(report["cleansing"]["applied"].get<bool>());
    EXPECT_EQ(nlohmann::json::parse(readWholeFile(summary)), report);

    // Nothing is replaced without --force.
    const auto again = runCvc("colon " + anatomyPhantom().string() + " -o " + out.string());
    EXPECT_EQ(again.exitCode, 1);
    EXPECT_NE(again.err.find("exists"), std::string::npos) << again.err;
    EXPECT_EQ(runCvc("colon " + anatomyPhantom().string() + " -o " + out.string() + " --force").exitCode, 0);
}

TEST(CvcColon, AScanWithoutAColonGetsOneClearLine) {
    const fs::path ball = tmp("colon_cli/ball.nrrd");
    ASSERT_EQ(runCvc("phantom --kind ball --size 24 --force -o " + ball.string()).exitCode, 0);
    const auto run = runCvc("colon " + ball.string() + " -o " + tmp("colon_cli/none").string());
    EXPECT_EQ(run.exitCode, 1);
    EXPECT_NE(run.err.find("cvc: error: no air-filled colon found among 1 air regions (1 outside the body"),
              std::string::npos)
        << run.err;
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 3) << "two progress lines and the error:\n" << run.err;
}

TEST(CvcRender, PathAutoFliesAlongTheCentrelineOfTheCleansedScan) {
    const fs::path display = testing_support::processTmp("colon_cli_tiny.json");
    std::ofstream(display) << R"({"name": "tiny", "box_size_m": [2.4, 2.4, 2.4], "map": "none", "walls": [
        {"name": "front", "width": 24, "height": 18}, {"name": "floor", "width": 24, "height": 24}]})";
    const fs::path out = tmp("colon_cli/auto");
    fs::remove_all(out);
    const std::string command = "render " + anatomyPhantom().string() + " --display " + display.string() +
                                " --path auto --frames 3 --path-step 4 -o " + out.string();
    const auto run = runCvc(command);
    ASSERT_EQ(run.exitCode, 0) << run.err;
    EXPECT_TRUE(fs::exists(out / "colon" / "colon.json"));
    EXPECT_TRUE(fs::exists(out / "frame_0002" / "left" / "front.png"));
    EXPECT_FALSE(fs::exists(out / "frame_0003"));
    const auto manifest = nlohmann::json::parse(readWholeFile(out / "render.json"));
    EXPECT_EQ(manifest["volume"], fs::absolute(out / "colon" / "cleansed.nrrd").string()) << "render the cleansed scan";
    // The first pose is the rectal end of the centreline, looking along it.
    const auto report = nlohmann::json::parse(readWholeFile(out / "colon" / "colon.json"));
    const auto& first = report["centreline_mm"][0];
    const auto& pose = manifest["poses"][0];
    ASSERT_TRUE(pose.contains("position_mm")) << pose.dump();
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(pose["position_mm"][a].get<double>(), first[a].get<double>(), 1e-6);

    // An occupied folder needs --resume or --force; --resume reuses the analysis.
    const auto refused = runCvc(command);
    EXPECT_EQ(refused.exitCode, 1);
    EXPECT_NE(refused.err.find("exists and is not empty"), std::string::npos) << refused.err;
    const auto resumed = runCvc(command + " --resume");
    ASSERT_EQ(resumed.exitCode, 0) << resumed.err;
    EXPECT_NE(resumed.err.find("colon: reusing the analysis"), std::string::npos) << resumed.err;
}

}  // namespace
