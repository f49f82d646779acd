// `cvc insert-polyp` as a user runs it on the shared abdominal CT: after `cvc colon`, a polyp at
// a centreline point, its truth carrying the centreline (so it works as `--path`), insertions
// stacked by running on the output again, nothing overwritten without --force, and one clear
// line for a point in tissue.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/support/run_program.h"
#include "volumes/load_volume.h"

namespace {

namespace fs = std::filesystem;
using testing_support::readWholeFile;
using testing_support::runCvc;

fs::path tmp(const std::string& name) { return fs::path(CVC_TEST_TMP_DIR) / name; }

/// "x,y,z" of the point `fraction` of the way along segment `s` of a colon.json.
std::string pointOfSegment(const nlohmann::json& report, std::size_t s, double fraction) {
    const auto& starts = report["segment_starts"];
    const std::size_t first = starts[s].get<std::size_t>();
    const std::size_t end = s + 1 < starts.size() ? starts[s + 1].get<std::size_t>() : report["centreline_mm"].size();
    const auto n = first + static_cast<std::size_t>(fraction * static_cast<double>(end - 1 - first));
    const auto& p = report["centreline_mm"][n];
    std::ostringstream text;
    text << p[0].get<double>() << ',' << p[1].get<double>() << ',' << p[2].get<double>();
    return text.str();
}

std::size_t longestSegment(const nlohmann::json& report) {
    std::size_t best = 0;
    for (std::size_t s = 0; s < report["segments"].size(); ++s) {
        if (report["segments"][s]["length_mm"] > report["segments"][best]["length_mm"]) best = s;
    }
    return best;
}

TEST(CvcInsertPolyp, PutsAPolypOnTheSharedCtWithItsTruthAndCentreline) {
    const std::string ct = std::string(CVC_SHARED_DATA_DIR) + "/ct/ts_example_abdomen_3mm.nrrd";
    if (!fs::exists(ct)) GTEST_SKIP() << ct << " is missing";
    const fs::path dir = tmp("insert_polyp_cli");
    fs::remove_all(dir);
    fs::create_directories(dir);
    const auto analysed = runCvc("colon " + ct + " -o " + (dir / "colon").string());
    ASSERT_EQ(analysed.exitCode, 0) << analysed.err;
    const auto report = nlohmann::json::parse(readWholeFile(dir / "colon" / "colon.json"));
    const std::size_t longest = longestSegment(report);

    const fs::path out = dir / "with_polyp.nrrd";
    const std::string command = "insert-polyp " + ct + " --at " + pointOfSegment(report, longest, 0.5) +
                                " --diameter 12 --centreline " + (dir / "colon" / "colon.json").string() + " -o " +
                                out.string() + " --json " + (dir / "summary.json").string();
    const auto run = runCvc(command);
    ASSERT_EQ(run.exitCode, 0) << run.err;
    EXPECT_NE(run.out.find("inserted a 12.0 mm sessile polyp at ("), std::string::npos) << run.out;
    EXPECT_EQ(testing_support::lineCount(run.out), 1) << run.out;
    ASSERT_TRUE(fs::exists(out));
    const auto truth = nlohmann::json::parse(readWholeFile(dir / "with_polyp.json"));
    ASSERT_EQ(truth["polyps"].size(), 1u);
    const auto& polyp = truth["polyps"][0];
    EXPECT_EQ(polyp["kind"], "sessile");
    EXPECT_DOUBLE_EQ(polyp["diameter_mm"].get<double>(), 12.0);
    EXPECT_DOUBLE_EQ(polyp["radius_mm"].get<double>(), 6.0);
    for (const char* key : {"centre_mm", "base_mm", "base_normal"}) EXPECT_EQ(polyp[key].size(), 3u) << key;
    EXPECT_GT(polyp["arc_length_mm"].get<double>(), 0.0) << "along the centreline it came with";
    EXPECT_GT(polyp["edge_width_mm"].get<double>(), 1.5) << "at least half the 3 mm spacing";
    EXPECT_EQ(truth["dims"], report["dims"]);
    EXPECT_EQ(truth["centreline_mm"], report["centreline_mm"]);
    EXPECT_EQ(truth["segment_starts"], report["segment_starts"]);
    EXPECT_EQ(truth["centreline_order"], "rectum_to_caecum");
    EXPECT_EQ(truth["anterior"], report["anterior"]);
    const auto summary = nlohmann::json::parse(readWholeFile(dir / "summary.json"));
    EXPECT_GT(summary["voxels_changed"].get<int>(), 10);
    EXPECT_EQ(summary["polyp"], polyp);
    // The output keeps the scan's grid and patient frame.
    const volumes::Volume original = volumes::loadVolume(ct), inserted = volumes::loadVolume(out.string());
    EXPECT_EQ(inserted.dims, original.dims);
    EXPECT_EQ(inserted.originLps, original.originLps);
    EXPECT_EQ(inserted.directionLps, original.directionLps);
    EXPECT_NE(inserted.hu, original.hu);

    // Nothing is replaced without --force.
    const auto again = runCvc(command);
    EXPECT_EQ(again.exitCode, 1);
    EXPECT_NE(again.err.find("exists already (pass --force"), std::string::npos) << again.err;
    EXPECT_EQ(runCvc(command + " --force").exitCode, 0);

    // Stacked: a second polyp further along, into the output, with the first truth as --centreline.
    const auto stacked = runCvc("insert-polyp " + out.string() + " --at " + pointOfSegment(report, longest, 0.25) +
                                " --diameter 12 --stalk 1 --centreline " + (dir / "with_polyp.json").string() +
                                " -o " + (dir / "two.nrrd").string());
    ASSERT_EQ(stacked.exitCode, 0) << stacked.err;
    const auto both = nlohmann::json::parse(readWholeFile(dir / "two.json"));
    ASSERT_EQ(both["polyps"].size(), 2u);
    EXPECT_EQ(both["polyps"][0], polyp);
    EXPECT_EQ(both["polyps"][1]["kind"], "pedunculated");
    EXPECT_EQ(both["centreline_mm"], report["centreline_mm"]);
}

TEST(CvcInsertPolyp, APointInTissueGetsOneClearLine) {
    const std::string ct = std::string(CVC_SHARED_DATA_DIR) + "/ct/ts_example_abdomen_3mm.nrrd";
    if (!fs::exists(ct)) GTEST_SKIP() << ct << " is missing";
    // A soft-tissue voxel near the middle of the scan.
    const volumes::Volume volume = volumes::loadVolume(ct);
    std::string at;
    for (int i = volume.dims[0] / 2; i < volume.dims[0] && at.empty(); ++i) {
        const int j = volume.dims[1] / 2, k = volume.dims[2] / 2;
        if (volume.at(i, j, k) > 20 && volume.at(i, j, k) < 80) {
            std::ostringstream text;
            text << i * volume.spacingMm.x << ',' << j * volume.spacingMm.y << ',' << k * volume.spacingMm.z;
            at = text.str();
        }
    }
    ASSERT_FALSE(at.empty());
    fs::remove(tmp("insert_polyp_tissue.nrrd"));
    const auto run = runCvc("insert-polyp " + ct + " --at " + at + " --diameter 12 --force -o " +
                            tmp("insert_polyp_tissue.nrrd").string());
    EXPECT_EQ(run.exitCode, 1);
    EXPECT_NE(run.err.find("cvc: error: polyp insertion: the point ("), std::string::npos) << run.err;
    EXPECT_NE(run.err.find("is not in the lumen (HU "), std::string::npos) << run.err;
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 2) << "the loading note and the error:\n" << run.err;
    EXPECT_FALSE(fs::exists(tmp("insert_polyp_tissue.nrrd")));
}

TEST(CvcInsertPolyp, ACentrelineWithBadPointsIsRefusedBeforeLoading) {
    // Points that are not three numbers: the path reader's message, not the JSON library's.
    const fs::path centreline = tmp("insert_polyp_bad_centreline.json");
    std::ofstream(centreline) << R"({"centreline_mm": [[1, 2, 3], ["x", 2, 3]]})";
    const auto run = runCvc("insert-polyp nowhere.nrrd --at 1,2,3 --diameter 8 --force --centreline " +
                            centreline.string() + " -o " + tmp("insert_polyp_bad.nrrd").string());
    EXPECT_EQ(run.exitCode, 1);
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
    EXPECT_NE(run.err.find("cvc: error: " + centreline.string()), std::string::npos) << run.err;
    EXPECT_EQ(run.err.find("type_error"), std::string::npos) << run.err;
    EXPECT_FALSE(fs::exists(tmp("insert_polyp_bad.nrrd")));
}

}  // namespace
