// `cvc candidates` as a user runs it: on the default colon phantom every polyp of 6 mm and more
// is found (against the phantom's truth, an oracle the rule never sees) with its diameter, each
// candidate placed on a frame of the path; the files it writes; refusing to overwrite; one clear
// line for a scan without a colon and for a path outside the volume; `cvc polyp-check
// --candidates` checking a candidate as its truth would be checked.
#include <algorithm>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "tests/support/run_program.h"

namespace {

namespace fs = std::filesystem;
using testing_support::readWholeFile;
using testing_support::runCvc;

fs::path tmp(const std::string& name) { return fs::path(CVC_TEST_TMP_DIR) / "candidates_cli" / name; }

glm::dvec3 vec(const nlohmann::json& v) { return {v[0].get<double>(), v[1].get<double>(), v[2].get<double>()}; }

/// The default colon phantom (five polyps of 3 to 12 mm), made once.
const fs::path& phantom() {
    static const fs::path volume = [] {
        fs::create_directories(tmp(""));
        const fs::path path = testing_support::processTmp("candidates_phantom.nrrd");
        const auto run = runCvc("phantom --force -o " + path.string());
        EXPECT_EQ(run.exitCode, 0) << run.err;
        return path;
    }();
    return volume;
}

/// A candidate marks a polyp when its centre lies within the polyp's radius and 3 mm of the
/// polyp's centre or of its apex (its base moved its height along the wall's normal).
bool marks(const nlohmann::json& candidate, const nlohmann::json& polyp) {
    const glm::dvec3 c = vec(candidate["centre_mm"]);
    const glm::dvec3 apex = vec(polyp["base_mm"]) + polyp["height_mm"].get<double>() * vec(polyp["base_normal"]);
    const double reach = 0.5 * polyp["diameter_mm"].get<double>() + 3.0;
    return std::min(glm::length(c - vec(polyp["centre_mm"])), glm::length(c - apex)) <= reach;
}

TEST(CvcCandidates, FindsThePhantomsPolypsOfSixMillimetresAndMoreOnFramesOfThePath) {
    const fs::path out = tmp("phantom");
    fs::remove_all(out);
    const fs::path summary = tmp("summary.json");
    fs::remove(summary);
    const auto run = runCvc("candidates " + phantom().string() + " -o " + out.string() + " --json " + summary.string());
    ASSERT_EQ(run.exitCode, 0) << run.err;
    EXPECT_NE(run.err.find("candidates: colon [4/4] done"), std::string::npos) << run.err;
    for (const char* name : {"candidates.json", "candidates.mrk.json", "candidate_01.png"}) {
        EXPECT_TRUE(fs::exists(out / name)) << name;
    }
    const auto doc = nlohmann::json::parse(readWholeFile(out / "candidates.json"));
    EXPECT_EQ(nlohmann::json::parse(readWholeFile(summary)), doc);
    const auto truth = nlohmann::json::parse(readWholeFile(fs::path(phantom()).replace_extension(".json")));
    const auto& candidates = doc["candidates"];
    const int frames = doc["path"]["frames"].get<int>();
    ASSERT_GT(frames, 100);

    std::vector<bool> isMatched(candidates.size(), false);
    int large = 0;
    for (const auto& polyp : truth["polyps"]) {
        const double diameter = polyp["diameter_mm"].get<double>();
        const auto found = std::find_if(candidates.begin(), candidates.end(), [&](const auto& c) { return marks(c, polyp); });
        for (std::size_t i = 0; i < candidates.size(); ++i) isMatched[i] = isMatched[i] || marks(candidates[i], polyp);
        if (diameter < 6.0) continue;
        ++large;
        ASSERT_NE(found, candidates.end()) << polyp.dump();
        EXPECT_NEAR((*found)["diameter_mm"].get<double>(), diameter, 0.25 * diameter) << polyp.dump();
        EXPECT_GT((*found)["shape_index"].get<double>(), 0.9);
    }
    EXPECT_EQ(large, 4);
    EXPECT_LE(std::count(isMatched.begin(), isMatched.end(), false), 2) << "false positives";
    double previousScore = 2.0;
    for (const auto& c : candidates) {
        const int frame = c["nearest_frame"].get<int>();
        EXPECT_GE(frame, 0);
        EXPECT_LT(frame, frames);
        EXPECT_GE(c["arc_length_mm"].get<double>(), 0.0);
        // A frame every 2 mm: the nearest frame lies at about the candidate's arc length.
        EXPECT_NEAR(frame * doc["path"]["step_mm"].get<double>(), c["arc_length_mm"].get<double>(), 6.0);
        EXPECT_LE(c["score"].get<double>(), previousScore);
        previousScore = c["score"].get<double>();
    }
    const auto markups = nlohmann::json::parse(readWholeFile(out / "candidates.mrk.json"));
    EXPECT_EQ(markups["markups"][0]["controlPoints"].size(), candidates.size());

    // Nothing is replaced without --force.
    const auto again = runCvc("candidates " + phantom().string() + " -o " + out.string());
    EXPECT_EQ(again.exitCode, 1);
    EXPECT_NE(again.err.find("candidates.json exists (use --force to replace it)"), std::string::npos) << again.err;
}

// A second method for the check's own input: the 12 mm polyp of the default phantom checked through
// the map once from its truth and once as the candidate that marks it (a cap of the measured
// size, cvc candidates' sphere): the same shapes come out, within two points.
TEST(CvcCandidates, PolypCheckTakesTheCandidatesForATruth) {
    const fs::path found = tmp("for_polyp_check");
    ASSERT_EQ(runCvc("candidates " + phantom().string() + " --pictures 0 --force -o " + found.string()).exitCode, 0);
    const auto candidates = nlohmann::json::parse(readWholeFile(found / "candidates.json"))["candidates"];
    const auto truth = nlohmann::json::parse(readWholeFile(fs::path(phantom()).replace_extension(".json")))["polyps"];
    const std::size_t polyp = 3;
    ASSERT_EQ(truth[polyp]["diameter_mm"].get<double>(), 12.0);
    int marking = -1;
    for (std::size_t i = 0; i < candidates.size() && marking < 0; ++i) {
        if (marks(candidates[i], truth[polyp])) marking = static_cast<int>(i);
    }
    ASSERT_GE(marking, 0);
    const std::string common = " --wall-size 700x525 --poses edge --force -o ";
    const auto asCandidate = runCvc("polyp-check " + phantom().string() + " --candidates " +
                                    (found / "candidates.json").string() + " --polyps " + std::to_string(marking) +
                                    common + tmp("check_candidate").string());
    ASSERT_EQ(asCandidate.exitCode, 0) << asCandidate.err;
    const auto asTruth = runCvc("polyp-check " + phantom().string() + " --truth " +
                                fs::path(phantom()).replace_extension(".json").string() + " --polyps 3" + common +
                                tmp("check_truth").string());
    ASSERT_EQ(asTruth.exitCode, 0) << asTruth.err;
    const auto fromCandidate = nlohmann::json::parse(readWholeFile(tmp("check_candidate") / "polyp_check.json"));
    const auto fromTruth = nlohmann::json::parse(readWholeFile(tmp("check_truth") / "polyp_check.json"));
    EXPECT_EQ(fromCandidate["truth"], fs::absolute(found / "candidates.json").string());
    ASSERT_EQ(fromCandidate["results"].size(), 9u);  // 1 pose x 3 eyes x 3 maps
    int compared = 0;
    for (const auto& c : fromCandidate["results"]) {
        if (c["map"] != "conformal") continue;
        for (const auto& t : fromTruth["results"]) {
            if (t["map"] != c["map"] || t["eye"] != c["eye"] || t["pose"] != c["pose"]) continue;
            ASSERT_TRUE(c["visible"].get<bool>() && t["visible"].get<bool>()) << c["eye"];
            EXPECT_LT(c["aspect_error"].get<double>(), 0.03) << c["eye"];
            EXPECT_NEAR(c["aspect_error"].get<double>(), t["aspect_error"].get<double>(), 0.02) << c["eye"];
            EXPECT_NEAR(c["circularity_error"].get<double>(), t["circularity_error"].get<double>(), 0.02) << c["eye"];
            ++compared;
        }
    }
    EXPECT_EQ(compared, 3);
}

TEST(CvcCandidates, BadInputGetsOneClearLine) {
    const fs::path ball = tmp("ball.nrrd");
    ASSERT_EQ(runCvc("phantom --kind ball --size 24 --force -o " + ball.string()).exitCode, 0);
    const auto noColon = runCvc("candidates " + ball.string() + " -o " + tmp("none").string());
    EXPECT_EQ(noColon.exitCode, 1);
    EXPECT_NE(noColon.err.find("cvc: error: no air-filled colon found"), std::string::npos) << noColon.err;

    // A path from another scan: refused before the analysis runs.
    const fs::path path = tmp("far_path.txt");
    std::ofstream(path) << "10 10 10\n20 20 20\n900 20 20\n";
    const auto farPath = runCvc("candidates " + phantom().string() + " --path " + path.string() + " -o " +
                                tmp("far").string() + " --force");
    EXPECT_EQ(farPath.exitCode, 1);
    EXPECT_NE(farPath.err.find("far_path.txt: point 3 of segment 1 (900.0, 20.0, 20.0 mm) lies outside the volume"),
              std::string::npos)
        << farPath.err;
    EXPECT_EQ(farPath.err.find("colon ["), std::string::npos) << farPath.err;
    EXPECT_EQ(testing_support::lineCount(farPath.err), 2) << "the loading line and the error:\n" << farPath.err;

    // A list placed on frames 2 mm apart does not name the frames of a fly-through at 5 mm.
    const fs::path placed = tmp("placed");
    ASSERT_EQ(runCvc("candidates " + phantom().string() + " --pictures 0 --force -o " + placed.string()).exitCode, 0);
    const auto otherStep = runCvc("render " + phantom().string() + " --display ic5 --path " +
                                  fs::path(phantom()).replace_extension(".json").string() + " --path-step 5 --candidates " +
                                  (placed / "candidates.json").string() + " --force -o " + tmp("other_step").string());
    EXPECT_EQ(otherStep.exitCode, 1);
    EXPECT_NE(otherStep.err.find("its candidates were placed on frames 2 mm apart, this render's are 5 mm apart"),
              std::string::npos)
        << otherStep.err;
    EXPECT_FALSE(fs::exists(tmp("other_step") / "frame_0000"));

    // polyp-check takes a truth or a candidate list, not both and not neither.
    const auto neither = runCvc("polyp-check " + phantom().string() + " -o " + tmp("neither").string());
    EXPECT_EQ(neither.exitCode, 1);
    EXPECT_NE(neither.err.find("cvc: error: polyp-check needs --truth or --candidates"), std::string::npos) << neither.err;
    const auto both = runCvc("polyp-check " + phantom().string() + " --truth a.json --candidates b.json -o " +
                             tmp("both").string());
    EXPECT_NE(both.exitCode, 0);
    EXPECT_NE(both.err.find("excludes"), std::string::npos) << both.err;
}

}  // namespace
