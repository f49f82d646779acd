/// @brief The processes of one run started by mpirun (Open MPI): this one's rank, how many there
/// are, a barrier, a broadcast from rank 0, a gather and messages to it, and a job-wide stop.
/// Built without MPI, or run without mpirun, it is rank 0 of 1 and every call returns at once,
/// so the program behaves as before.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace distribution {

class MpiSession {
public:
    /// Starts MPI when this process was launched by mpirun (its environment says so) and the
    /// program was built with MPI; before any Vulkan device is made, sets LP_NUM_THREADS so that
    /// the ranks on one machine share its cores (see threadsPerRank) unless the user set it.
    MpiSession(int* argc, char*** argv);
    /// One process, no MPI.
    MpiSession();
    ~MpiSession();
    MpiSession(const MpiSession&) = delete;
    MpiSession& operator=(const MpiSession&) = delete;

    [[nodiscard]] int rank() const { return mRank; }
    [[nodiscard]] int ranks() const { return mRanks; }
    [[nodiscard]] bool isShared() const { return mRanks > 1; }

    /// Returns once every rank called it (and this rank's sends to rank 0 are complete).
    void barrier();
    /// Rank 0's `text` on every rank.
    [[nodiscard]] std::string broadcast(const std::string& text) const;
    /// Every rank's `text` on rank 0, in rank order (the others get an empty list).
    [[nodiscard]] std::vector<std::string> gather(const std::string& text) const;
    /// Sends `message` to rank 0 without waiting for it to be received (rank 0 takes it with
    /// receiveAtRoot); the message is kept until MPI is done with it. The barrier completes the
    /// sends, so rank 0 must have received them all before it enters the barrier.
    void sendToRoot(std::vector<unsigned char> message);
    /// On rank 0: a message another rank sent, if one has arrived (never waits).
    [[nodiscard]] std::optional<std::vector<unsigned char>> receiveAtRoot() const;
    /// Every rank's "host pid" on rank 0, in rank order (see gather).
    [[nodiscard]] std::vector<std::string> gatherProcesses() const;
    /// Stops every rank of the job with `code` (after this rank printed why).
    [[noreturn]] void abort(int code) const;

    /// The lavapipe threads each rank gets: the machine's cores divided among the ranks on it, at
    /// least one.
    static int threadsPerRank(int cores, int ranksOnMachine);

private:
    int mRank = 0;
    int mRanks = 1;
    bool mIsStarted = false;
    struct PendingSends;  // messages on their way to rank 0 (MPI types stay in the .cpp)
    std::unique_ptr<PendingSends> mSends;
    void completeSends();
};

/// This machine's host name (empty when it cannot be read).
std::string thisHostName();

/// The session main() made (rank 0 of 1 before that).
MpiSession& mpiSession();

}  // namespace distribution
