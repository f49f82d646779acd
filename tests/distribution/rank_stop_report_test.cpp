// The report rank 0 writes when mpirun stops a shared render: the rank whose process is gone
// and the first of its frames it had not written, how many frames are in place, and nothing
// written past the buffer it is given (it is composed in a signal handler).
#include <cstring>
#include <filesystem>
#include <string>

#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "distribution/rank_stop_report.h"
#include "engine/sequence/frame_sequence.h"
#include "tests/support/run_program.h"

namespace {

namespace fs = std::filesystem;

/// The pid of a process that ended and was reaped, as mpirun reaps a killed rank.
long endedPid() {
    const pid_t child = fork();
    if (child == 0) _exit(0);
    int status = 0;
    waitpid(child, &status, 0);
    return child;
}

/// Two ranks dealt frames 0-5 as the frames distribution deals them (rank 0 the even ones);
/// frames 0 and 2 are in place, rank 1 wrote frame 1 (waiting for rank 0's sheet) and was at 3.
struct TwoRankFolder {
    TwoRankFolder() {
        fs::remove_all(folder);
        for (int frame : {0, 2}) fs::create_directories(folder / engine::frameFolderName(frame));
        fs::create_directories(folder / engine::writtenFrameFolderName(1));
        fs::create_directories(folder / engine::partialFrameFolderName(3));
    }
    distribution::RankStopState state(long rank1Pid, const std::string& rank1Host) const {
        const std::vector<distribution::RankProcess> processes = {{"here", static_cast<long>(getpid())}, {rank1Host, rank1Pid}};
        return distribution::rankStopStateOf(folder.string(), "here", processes, {{0, 2, 4}, {1, 3, 5}}, 6);
    }
    fs::path folder = testing_support::processTmp("rank_stop_folder");
};

std::string reportOf(const distribution::RankStopState& state) {
    char buffer[4096];
    const std::size_t length = distribution::composeRankStopReport(state, buffer, sizeof buffer);
    EXPECT_EQ(length, std::strlen(buffer));
    return buffer;
}

TEST(RankStopReport, NamesTheEndedRankAndTheFirstFrameItHadNotWritten) {
    const TwoRankFolder made;
    const long pid = endedPid();
    const std::string report = reportOf(made.state(pid, "here"));
    EXPECT_NE(report.find("rank 1 (pid " + std::to_string(pid) + ") ended while at frame 3"), std::string::npos)
        << report;
    EXPECT_EQ(report.find("rank 0 ("), std::string::npos) << "rank 0 is alive: " << report;
    EXPECT_NE(report.find("3 of 6 frames are finished in " + made.folder.string() +
                          " and kept (1 with every image, waiting only for the sheet)"),
              std::string::npos)
        << report;
    EXPECT_NE(report.find("--resume"), std::string::npos) << report;
    EXPECT_EQ(report.rfind("cvc: error: ", 0), 0u) << report;
    EXPECT_EQ(report.back(), '\n');
}

TEST(RankStopReport, ARankThatWroteAllItsFramesIsSaidToHaveDoneSo) {
    const TwoRankFolder made;
    for (int frame : {3, 5}) fs::create_directories(made.folder / engine::writtenFrameFolderName(frame));
    const std::string report = reportOf(made.state(endedPid(), "here"));
    EXPECT_NE(report.find("ended after writing all its frames"), std::string::npos) << report;
}

TEST(RankStopReport, WithoutAnEndedRankHereItSaysWhereEachRankWas) {
    // A gone process on another machine cannot be seen from here: no rank is called ended.
    const TwoRankFolder made;
    const std::string report = reportOf(made.state(endedPid(), "elsewhere"));
    EXPECT_EQ(report.find("ended "), std::string::npos) << report;
    EXPECT_NE(report.find("rank 0 at frame 4, rank 1 at frame 3"), std::string::npos) << report;
    EXPECT_NE(report.find("3 of 6 frames are finished"), std::string::npos) << report;
}

TEST(RankStopReport, StaysInsideASmallBuffer) {
    const TwoRankFolder made;
    char buffer[24];
    std::memset(buffer, 'x', sizeof buffer);
    const std::size_t length = distribution::composeRankStopReport(made.state(endedPid(), "here"), buffer, 16);
    EXPECT_EQ(length, 15u);
    EXPECT_EQ(buffer[15], '\0');
    EXPECT_EQ(std::string(buffer), std::string("cvc: error: ran"));
    for (std::size_t i = 16; i < sizeof buffer; ++i) EXPECT_EQ(buffer[i], 'x') << "written past the buffer at " << i;
}

TEST(RankStopReport, ReadsTheGatheredProcesses) {
    const auto processes = distribution::rankProcessesOf({"node-a 4242", "node b 17", "garbage", "node-c -5", "node-d 12x"});
    ASSERT_EQ(processes.size(), 5u);
    EXPECT_EQ(processes[0].host, "node-a");
    EXPECT_EQ(processes[0].pid, 4242);
    EXPECT_EQ(processes[1].host, "node b");  // the pid is after the last space
    EXPECT_EQ(processes[1].pid, 17);
    for (std::size_t i = 2; i < processes.size(); ++i) EXPECT_EQ(processes[i].pid, 0) << i;  // never found ended
}

}  // namespace
