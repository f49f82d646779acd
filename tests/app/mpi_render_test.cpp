// `mpirun -np 2 cvc render --display` as a cluster runs it: the output folder equals the
// single-process folder byte for byte under both distributions (and under one rank), coverage
// and the polyp check give what one process gives, other commands are refused, and a rank killed
// mid-run stops the job with rank 0 naming the rank and its frame, keeps the finished frames, and `--resume`
// with one process completes the folder to equal a clean run.
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <cctype>
#include <map>
#include <string>
#include <thread>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/support/folder_compare.h"
#include "tests/support/run_program.h"

namespace {

namespace fs = std::filesystem;
using testing_support::expectSameFolders;
using testing_support::readWholeFile;
using testing_support::runCvc;

// Root in CI: Open MPI refuses root without the flag. Two ranks on any core count.
const std::string kMpirun = "mpirun -np 2 --oversubscribe --allow-run-as-root";

struct Fixture {
    fs::path volume, truth, display;
};

/// A small colon phantom and a small 5-wall display with the conformal map.
const Fixture& fixture() {
    static const Fixture f = [] {
        Fixture made;
        made.volume = testing_support::processTmp("mpi_colon.nrrd");
        made.truth = fs::path(made.volume).replace_extension(".json");
        made.display = testing_support::processTmp("mpi_display.json");
        const auto run = runCvc("phantom --size 96 --spacing 1.6 --force -o " + made.volume.string());
        EXPECT_EQ(run.exitCode, 0) << run.err;
        std::ofstream(made.display) << R"({"name": "ic5_small", "box_size_m": [2.95, 2.21, 2.95], "map": "conformal",
          "walls": [{"name": "front", "width": 112, "height": 84}, {"name": "back", "width": 112, "height": 84},
                    {"name": "left", "width": 112, "height": 84}, {"name": "right", "width": 112, "height": 84},
                    {"name": "floor", "width": 84, "height": 84}]})";
        return made;
    }();
    return f;
}

/// Frames 12 mm apart, or 3 mm apart for a run long enough to be killed half way.
double stepFor(int frames) { return frames > 10 ? 3.0 : 12.0; }

std::string renderArguments(const fs::path& out, int frames, const std::string& more = "") {
    const Fixture& f = fixture();
    return "render " + f.volume.string() + " --display " + f.display.string() + " --path " + f.truth.string() +
           " --path-step " + std::to_string(stepFor(frames)) + " --frames " + std::to_string(frames) +
           " --map-size 64 --before-after --force -o " + out.string() + " " + more;
}

std::string frameName(int index) {
    std::string name = std::to_string(index);
    return "frame_" + std::string(4 - std::min<std::size_t>(4, name.size()), '0') + name;
}

/// K of rank 0's report "rank 1 (pid N) ended while at frame K", or -1 when it is not there.
/// Read by hand: GCC 12's <regex> draws -Wmaybe-uninitialized warnings at -O1.
int frameNamedForRank1(const std::string& err) {
    const std::string head = "rank 1 (pid ";
    const std::string tail = ") ended while at frame ";
    const std::size_t at = err.find(head);
    if (at == std::string::npos) return -1;
    const std::size_t pidEnd = err.find(tail, at);
    if (pidEnd == std::string::npos) return -1;
    const std::string pid = err.substr(at + head.size(), pidEnd - at - head.size());
    if (pid.empty() || pid.find_first_not_of("0123456789") != std::string::npos) return -1;
    const std::size_t frameStart = pidEnd + tail.size();
    std::size_t frameEnd = frameStart;
    while (frameEnd < err.size() && std::isdigit(static_cast<unsigned char>(err[frameEnd])) != 0) ++frameEnd;
    return frameEnd > frameStart ? std::stoi(err.substr(frameStart, frameEnd - frameStart)) : -1;
}

/// The single-process folder of `frames` frames (made once per frame count).
const fs::path& reference(int frames) {
    static std::map<int, fs::path> made;
    auto found = made.find(frames);
    if (found == made.end()) {
        const fs::path out = testing_support::processTmp("mpi_reference_" + std::to_string(frames));
        const auto run = runCvc(renderArguments(out, frames));
        EXPECT_EQ(run.exitCode, 0) << run.err;
        found = made.emplace(frames, out).first;
    }
    return found->second;
}

TEST(CvcMpiRender, TwoRanksWriteTheSingleProcessFolderUnderBothDistributions) {
    for (const std::string distribution : {"frames", "walls"}) {
        const fs::path out = testing_support::processTmp("mpi_two_ranks_" + distribution);
        const auto run = runCvc(renderArguments(out, 3, "--distribute " + distribution), kMpirun);
        ASSERT_EQ(run.exitCode, 0) << distribution << ": " << run.err;
        EXPECT_NE(run.out.find("x 2 ranks (" + distribution + ")"), std::string::npos) << run.out;
        // One summary, from rank 0.
        std::size_t summaries = 0;
        for (std::size_t at = run.out.find("rendered "); at != std::string::npos; at = run.out.find("rendered ", at + 1)) ++summaries;
        EXPECT_EQ(summaries, 1u) << run.out;
        // Rank 0 writes every sheet: of 3 frames, that of rank 1's frame 1 (frames) or all 3,
        // where rank 1 rendered the back and right walls (walls).
        const std::string sheets = distribution == "frames" ? "wrote 1 sheet(s)" : "wrote 3 sheet(s)";
        EXPECT_NE(run.out.find("rank 0 " + sheets + " of other ranks' walls"), std::string::npos) << run.out;
        expectSameFolders(reference(3), out);
    }
}

TEST(CvcMpiRender, OneRankUnderMpirunChangesNothingAndOtherCommandsAreRefused) {
    const fs::path out = testing_support::processTmp("mpi_one_rank");
    const auto run = runCvc(renderArguments(out, 3), "mpirun -np 1 --allow-run-as-root");
    ASSERT_EQ(run.exitCode, 0) << run.err;
    expectSameFolders(reference(3), out);
    // Commands that do not share their work would run it twice over the same files.
    const auto phantom = runCvc("phantom --force -o " + testing_support::processTmp("mpi_refused.nrrd").string(), kMpirun);
    EXPECT_NE(phantom.exitCode, 0);
    EXPECT_NE(phantom.err.find("only `cvc render --display`, `cvc coverage` and `cvc polyp-check`"), std::string::npos)
        << phantom.err;
    EXPECT_FALSE(fs::exists(testing_support::processTmp("mpi_refused.nrrd")));
}

TEST(CvcMpiCoverage, TwoRanksMeasureWhatOneProcessMeasures) {
    // Frames split between the ranks, their first sightings merged by rank 0 in frame order: the
    // same figure, curve and patches as one process, the same sheets.
    const Fixture& f = fixture();
    const auto coverageArguments = [&](const fs::path& out) {
        return "coverage " + f.volume.string() + " --path " + f.truth.string() + " --display " + f.display.string() +
               " --path-step 12 --frames 5 --map-size 64 --patch-pictures 2 --force -o " + out.string();
    };
    const fs::path single = testing_support::processTmp("mpi_coverage_single");
    const fs::path shared = testing_support::processTmp("mpi_coverage_shared");
    const auto one = runCvc(coverageArguments(single));
    ASSERT_EQ(one.exitCode, 0) << one.err;
    const auto two = runCvc(coverageArguments(shared), kMpirun);
    ASSERT_EQ(two.exitCode, 0) << two.err;
    const auto a = nlohmann::json::parse(readWholeFile(single / "coverage.json"));
    const auto b = nlohmann::json::parse(readWholeFile(shared / "coverage.json"));
    EXPECT_EQ(b["ranks"], 2);
    for (const char* key : {"coverage_percent", "seen_mm2", "wall_mm2", "cumulative_percent", "patches", "frames"}) {
        EXPECT_EQ(a[key], b[key]) << key;
    }
    for (int i = 0; i < 5; ++i) {
        const std::string sheet = "frame_000" + std::to_string(i) + "/sheet.png";
        EXPECT_TRUE(readWholeFile(single / sheet) == readWholeFile(shared / sheet)) << sheet;
    }
    EXPECT_TRUE(fs::exists(shared / "index.html"));
}

TEST(CvcMpiPolypCheck, TwoRanksWriteWhatOneProcessWrites) {
    // Polyps dealt out between the ranks, the entries put back in one process's order by rank 0:
    // the same JSON, table and crops, byte for byte.
    const Fixture& f = fixture();
    const auto arguments = [&](const fs::path& out) {
        return "polyp-check " + f.volume.string() + " --truth " + f.truth.string() +
               " --polyps 2 3 --poses wall,ceiling_50 --wall-size 280x210 --map-size 64 --force -o " + out.string();
    };
    const fs::path single = testing_support::processTmp("mpi_polyps_single");
    const fs::path shared = testing_support::processTmp("mpi_polyps_shared");
    const auto one = runCvc(arguments(single));
    ASSERT_EQ(one.exitCode, 0) << one.err;
    const auto two = runCvc(arguments(shared), kMpirun);
    ASSERT_EQ(two.exitCode, 0) << two.err;
    expectSameFolders(single, shared);
}

TEST(CvcMpiRender, AKilledRankStopsTheJobAndResumeCompletesTheFolder) {
    // Long enough (80 frames, some seconds) that the kill lands after the first frame and well
    // before the last, on any machine this runs on.
    constexpr int kFrames = 80;
    const fs::path out = testing_support::processTmp("mpi_killed");
    fs::remove_all(out);
    // Rank 1 is killed once the first frame is in place: find it by the rank Open MPI gave it.
    const fs::path killer = testing_support::processTmp("mpi_killer.sh");
    std::ofstream(killer) << "#!/bin/sh\n"
                             "for i in $(seq 3000); do [ -d '" << (out / "frame_0000").string() << "' ] && break; sleep 0.02; done\n"
                             "for p in $(pgrep -f -- '-o " << out.string() << " '); do\n"
                             "  if tr '\\0' '\\n' < /proc/$p/environ 2>/dev/null | grep -qx OMPI_COMM_WORLD_RANK=1; then kill -9 $p; fi\n"
                             "done\n";
    fs::permissions(killer, fs::perms::owner_all);
    std::thread watcher([&] { std::system(killer.string().c_str()); });
    const auto run = runCvc(renderArguments(out, kFrames, "--distribute frames"), kMpirun);
    watcher.join();
    EXPECT_NE(run.exitCode, 0);
    int inPlace = 0;
    for (int i = 0; i < kFrames; ++i) inPlace += fs::is_directory(out / frameName(i)) ? 1 : 0;
    EXPECT_GE(inPlace, 1);
    EXPECT_LT(inPlace, kFrames) << "the run was not stopped before its end";
    // Rank 0 names the rank that died and the frame it was at: one of rank 1's (the odd frames
    // of a fresh run of two ranks) that is not in place, and counts the frames kept.
    const int frameAt = frameNamedForRank1(run.err);
    ASSERT_GE(frameAt, 0) << run.err;
    EXPECT_EQ(frameAt % 2, 1) << run.err;
    const auto isWritten = [&](int frame) {  // in place, or written by rank 1 and waiting for rank 0's sheet
        std::string written = ".";  // appended piece by piece: GCC 12 warns (-Wrestrict) on "." + a + b
        written += frameName(frame);
        written += ".written";
        return fs::is_directory(out / frameName(frame)) || fs::is_directory(out / written);
    };
    EXPECT_FALSE(isWritten(frameAt)) << run.err;
    for (int frame = 1; frame < frameAt; frame += 2) {
        EXPECT_TRUE(isWritten(frame)) << "rank 1 had not written frame " << frame << ", before the one named";
    }
    // Kept: in place, or written whole by rank 1 and waiting for rank 0's sheet.
    int kept = 0;
    for (int i = 0; i < kFrames; ++i) kept += isWritten(i) ? 1 : 0;
    EXPECT_NE(run.err.find(std::to_string(kept) + " of " + std::to_string(kFrames) + " frames are finished"),
              std::string::npos)
        << run.err;
    // " 3 5": the hidden folders of frames being written when the job stopped (rendered again),
    // and of frames rank 1 wrote whole (finished from their images).
    std::string halfWritten;
    std::string wholeWritten;
    for (int i = 0; i < kFrames; ++i) {
        // Appended piece by piece: GCC 12 warns (-Wrestrict) on "." + a + b.
        std::string hidden = ".";
        hidden += frameName(i);
        if (fs::exists(out / (hidden + ".written"))) {
            wholeWritten += ' ';
            wholeWritten += std::to_string(i);
        } else if (fs::exists(out / (hidden + ".partial"))) {
            halfWritten += ' ';
            halfWritten += std::to_string(i);
        }
    }
    // One process finishes the rest.
    const Fixture& f = fixture();
    const auto resumed = runCvc("render " + f.volume.string() + " --display " + f.display.string() + " --path " +
                                f.truth.string() + " --path-step " + std::to_string(stepFor(kFrames)) + " --frames " +
                                std::to_string(kFrames) + " --map-size 64 --before-after --resume -o " + out.string());
    ASSERT_EQ(resumed.exitCode, 0) << resumed.err;
    EXPECT_NE(resumed.out.find("kept"), std::string::npos) << resumed.out;
    // The frames the killed job was writing (if it was killed while writing) are named.
    if (!halfWritten.empty()) {
        EXPECT_NE(resumed.out.find("the run that stopped was writing frame(s)" + halfWritten), std::string::npos)
            << resumed.out;
    }
    if (!wholeWritten.empty()) {
        EXPECT_NE(resumed.out.find("finished frame(s)" + wholeWritten + " from the images"), std::string::npos)
            << resumed.out;
    }
    expectSameFolders(reference(kFrames), out);
}

}  // namespace
