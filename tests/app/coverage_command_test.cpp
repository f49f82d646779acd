// `cvc coverage` as a user runs it: a short fly-through of the colon phantom on two displays,
// its JSON and folder, the order forward < ic6 on the same frames, and its refusals of bad input.
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/support/run_program.h"

namespace {

namespace fs = std::filesystem;
using testing_support::readWholeFile;
using testing_support::runCvc;

/// A small colon phantom (the default shape, coarser voxels) with its truth beside it.
const fs::path& phantom() {
    static const fs::path path = [] {
        const fs::path p = testing_support::processTmp("coverage_colon.nrrd");
        const auto run = runCvc("phantom --size 128 --spacing 1.2 --force -o " + p.string());
        EXPECT_EQ(run.exitCode, 0) << run.err;
        return p;
    }();
    return path;
}

std::string truth() { return fs::path(phantom()).replace_extension(".json").string(); }

nlohmann::json coverageOf(const std::string& display, const std::string& name) {
    const fs::path out = testing_support::processTmp(name);
    const fs::path json = testing_support::processTmp(name + ".json");
    const auto run = runCvc("coverage " + phantom().string() + " --path " + truth() + " --display " + display +
                            " --wall-size 120x90 --path-step 8 --frames 6 --patch-pictures 2 --force -o " +
                            out.string() + " --json " + json.string());
    EXPECT_EQ(run.exitCode, 0) << run.err;
    EXPECT_TRUE(fs::exists(out / "index.html"));
    EXPECT_TRUE(fs::exists(out / "coverage.png"));
    EXPECT_TRUE(fs::exists(out / "frame_0005" / "sheet.png"));
    return nlohmann::json::parse(readWholeFile(json));
}

TEST(CvcCoverage, ReportsCoverageAndItsUnseenPatchesLargestFirst) {
    const nlohmann::json forward = coverageOf("forward", "coverage_forward");
    const nlohmann::json ic6 = coverageOf("ic6", "coverage_ic6");
    for (const auto* doc : {&forward, &ic6}) {
        const double percent = (*doc)["coverage_percent"];
        EXPECT_GT(percent, 0.0);
        EXPECT_LE(percent, 100.0);
        EXPECT_NEAR((*doc)["seen_mm2"].get<double>(), percent / 100.0 * (*doc)["wall_mm2"].get<double>(), 1e-6 * percent);
        EXPECT_EQ((*doc)["frames"], 6);
        EXPECT_EQ((*doc)["cumulative_percent"].size(), 6u);
        double previous = 1e300;
        for (const auto& patch : (*doc)["patches"]) {
            EXPECT_LE(patch["area_mm2"].get<double>(), previous);
            previous = patch["area_mm2"];
        }
        const auto& first = (*doc)["patches"].at(0);
        EXPECT_TRUE(first.contains("pose"));
        EXPECT_TRUE(first["pose"].contains("look_at"));
    }
    // The same six frames: one screen ahead shows less than the whole cabin with its ceiling.
    EXPECT_LT(forward["coverage_percent"].get<double>(), ic6["coverage_percent"].get<double>());
    EXPECT_EQ(forward["wall_mm2"], ic6["wall_mm2"]);
}

TEST(CvcCoverage, RefusesBadInputWithOneLine) {
    const std::string base = "coverage " + phantom().string() + " --path " + truth() + " ";
    const fs::path out = testing_support::processTmp("coverage_refused");
    fs::create_directories(out);
    std::ofstream(out / "keep.txt") << "a reader's file";
    const auto occupied = runCvc(base + "-o " + out.string());
    EXPECT_NE(occupied.exitCode, 0);
    EXPECT_NE(occupied.err.find("not empty"), std::string::npos) << occupied.err;
    EXPECT_TRUE(fs::exists(out / "keep.txt"));
    for (const std::string& bad : {std::string("--retrograde --both-directions"), std::string("--max-angle 95"),
                                   std::string("--max-footprint 0"), std::string("--path-step 0"),
                                   std::string("--compare --map linear"), std::string("--display nowhere.json")}) {
        const auto run = runCvc(base + bad + " -o " + testing_support::processTmp("coverage_bad").string());
        EXPECT_NE(run.exitCode, 0) << bad;
        EXPECT_NE(run.err.find("error"), std::string::npos) << bad << ": " << run.err;
    }
    const auto noPath = runCvc("coverage " + phantom().string() + " --path /nonexistent.json -o " +
                               testing_support::processTmp("coverage_nopath").string());
    EXPECT_NE(noPath.exitCode, 0);
    EXPECT_NE(noPath.err.find("/nonexistent.json"), std::string::npos) << noPath.err;
}

}  // namespace
