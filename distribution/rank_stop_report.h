/// @brief What rank 0 says when mpirun stops a shared render. When a rank dies (killed, crashed)
/// mpirun names it and sends SIGTERM to the others, about a second before SIGKILL; rank 0 uses
/// that second to say which rank ended, the frame it was at, how many frames are finished and
/// that --resume completes the rest. The report is composed inside the signal handler, from the
/// folder's state (stat) and the ranks' process ids (kill with signal 0), so it uses only calls
/// a signal handler may make and nothing the interrupted code could be holding.
#pragma once

#include <atomic>
#include <cstddef>
#include <csignal>
#include <string>
#include <vector>

namespace distribution {

/// One rank's process, as MpiSession::gatherProcesses gives it ("host pid").
struct RankProcess {
    std::string host;
    long pid = 0;
};

/// Parses "host pid" texts, one per rank; an unreadable one gives pid 0 (never found ended).
std::vector<RankProcess> rankProcessesOf(const std::vector<std::string>& texts);

/// The state a report is composed from. Everything is prepared before the handler may read it.
struct RankStopState {
    std::string folder;                    // the render's output folder
    std::string host;                      // this machine: only its ranks can be found ended
    std::vector<RankProcess> processes;    // rank order
    std::vector<std::vector<int>> frames;  // the frames each rank renders (rank order, ascending)
    int framesTotal = 0;
    // Per frame of the job: its folder's path, and the hidden folder another rank fills before rank 0's sheet.
    std::vector<std::string> finishedPaths;
    std::vector<std::string> writtenPaths;
};

/// The state for `folder` once the pending frames are known: the paths a report stats.
RankStopState rankStopStateOf(const std::string& folder, const std::string& host,
                              std::vector<RankProcess> processes, std::vector<std::vector<int>> frames,
                              int framesTotal);

/// Writes the report into `buffer` (at most `size` - 1 characters and a terminating zero) and
/// returns its length. Safe in a signal handler: no allocation, no locks, only stat and kill.
/// A rank counts as ended when it ran on `state.host` and its process is gone; the frame a rank
/// was at is the first of its frames that is neither in place nor written (waiting for rank 0).
std::size_t composeRankStopReport(const RankStopState& state, char* buffer, std::size_t size);

/// Installs the SIGTERM handler on rank 0 of a shared run for its lifetime (the previous one
/// comes back after). The handler writes the report to stderr, then ends the process as
/// SIGTERM would have.
class RankStopReport {
public:
    /// `isOnTerminal`: stderr shows a progress bar, so the report starts on a new line.
    explicit RankStopReport(bool isOnTerminal);
    ~RankStopReport();
    RankStopReport(const RankStopReport&) = delete;
    RankStopReport& operator=(const RankStopReport&) = delete;

    /// Called once: from then on the handler reports `state` (before, it says only that the job
    /// was stopped).
    void arm(RankStopState state);

private:
    static void onTerminate(int signal);

    RankStopState mState;
    bool mIsOnTerminal;
    std::atomic<bool> mIsArmed{false};
    struct sigaction mPrevious {};
};

}  // namespace distribution
