#include "distribution/mpi_session.h"

#include <algorithm>
#include <cstdlib>
#include <iterator>
#include <limits>
#include <list>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <unistd.h>

#ifdef CVC_WITH_MPI
#include <mpi.h>
#endif

namespace distribution {
namespace {

MpiSession* gSession = nullptr;

/// The tag of the messages sent to rank 0 (the collectives use none).
constexpr int kToRootTag = 1;

/// An integer from the environment, or `fallback`.
int environmentInt(const char* name, int fallback) {
    const char* value = std::getenv(name);
    if (value == nullptr || *value == '\0') return fallback;
    char* end = nullptr;
    const long parsed = std::strtol(value, &end, 10);
    return (*end == '\0' && parsed > 0 && parsed < 1000000) ? static_cast<int>(parsed) : fallback;
}

/// mpirun (Open MPI's, or a PMIx launcher) sets these in every rank's environment.
bool isLaunchedByMpirun() { return std::getenv("OMPI_COMM_WORLD_SIZE") != nullptr || std::getenv("PMIX_RANK") != nullptr; }

#ifdef CVC_WITH_MPI
void check(int result, const char* what) {
    if (result != MPI_SUCCESS) throw std::runtime_error(std::string("MPI: ") + what + " failed");
}
#endif

}  // namespace

#ifdef CVC_WITH_MPI
struct MpiSession::PendingSends {
    struct Send {
        std::vector<unsigned char> message;  // where MPI reads from until the send completes
        MPI_Request request{};
    };
    std::list<Send> sends;  // a list: a message stays where it is while others come and go
};
#else
struct MpiSession::PendingSends {};
#endif

int MpiSession::threadsPerRank(int cores, int ranksOnMachine) {
    return std::max(1, std::max(cores, 1) / std::max(ranksOnMachine, 1));
}

MpiSession::MpiSession() = default;

MpiSession::MpiSession(int* argc, char*** argv) {
    gSession = this;
#ifdef CVC_WITH_MPI
    if (!isLaunchedByMpirun()) return;
    // Before MPI and Vulkan start: lavapipe reads LP_NUM_THREADS when its device is made.
    if (std::getenv("LP_NUM_THREADS") == nullptr) {
        const int local = environmentInt("OMPI_COMM_WORLD_LOCAL_SIZE", 1);
        const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
        setenv("LP_NUM_THREADS", std::to_string(threadsPerRank(cores, local)).c_str(), 0);
    }
    int provided = 0;
    check(MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided), "MPI_Init_thread");
    mIsStarted = true;
    check(MPI_Comm_rank(MPI_COMM_WORLD, &mRank), "MPI_Comm_rank");
    check(MPI_Comm_size(MPI_COMM_WORLD, &mRanks), "MPI_Comm_size");
#else
    (void)argc;
    (void)argv;
    (void)environmentInt;
    (void)isLaunchedByMpirun;
#endif
}

MpiSession::~MpiSession() {
#ifdef CVC_WITH_MPI
    if (mIsStarted) {
        try {
            completeSends();
        } catch (...) {
            // Finalizing anyway: the job is ending.
        }
        MPI_Finalize();
    }
#endif
    if (gSession == this) gSession = nullptr;
}

void MpiSession::completeSends() {
#ifdef CVC_WITH_MPI
    if (!mSends) return;
    for (auto& send : mSends->sends) check(MPI_Wait(&send.request, MPI_STATUS_IGNORE), "MPI_Wait");
    mSends->sends.clear();
#endif
}

void MpiSession::barrier() {
#ifdef CVC_WITH_MPI
    if (!mIsStarted) return;
    completeSends();
    check(MPI_Barrier(MPI_COMM_WORLD), "MPI_Barrier");
#endif
}

void MpiSession::sendToRoot(std::vector<unsigned char> message) {
#ifdef CVC_WITH_MPI
    if (!mIsStarted || mRanks == 1 || mRank == 0) {
        throw std::logic_error("MPI: only ranks other than 0 of a shared run send to rank 0");
    }
    if (message.size() > static_cast<std::size_t>(std::numeric_limits<int>::max())) {
        throw std::invalid_argument("MPI: a message of " + std::to_string(message.size()) + " bytes is too large");
    }
    if (!mSends) mSends = std::make_unique<PendingSends>();
    // Drop the messages rank 0 has received, so that a long run holds only those in flight.
    for (auto send = mSends->sends.begin(); send != mSends->sends.end();) {
        int isDone = 0;
        check(MPI_Test(&send->request, &isDone, MPI_STATUS_IGNORE), "MPI_Test");
        send = isDone != 0 ? mSends->sends.erase(send) : std::next(send);
    }
    auto& send = mSends->sends.emplace_back();
    send.message = std::move(message);
    check(MPI_Isend(send.message.data(), static_cast<int>(send.message.size()), MPI_BYTE, 0, kToRootTag,
                    MPI_COMM_WORLD, &send.request),
          "MPI_Isend");
#else
    (void)message;
    throw std::logic_error("MPI: only ranks other than 0 of a shared run send to rank 0");
#endif
}

std::optional<std::vector<unsigned char>> MpiSession::receiveAtRoot() const {
#ifdef CVC_WITH_MPI
    if (!mIsStarted || mRank != 0) return std::nullopt;
    int hasArrived = 0;
    MPI_Status status{};
    check(MPI_Iprobe(MPI_ANY_SOURCE, kToRootTag, MPI_COMM_WORLD, &hasArrived, &status), "MPI_Iprobe");
    if (hasArrived == 0) return std::nullopt;
    int size = 0;
    check(MPI_Get_count(&status, MPI_BYTE, &size), "MPI_Get_count");
    std::vector<unsigned char> message(static_cast<std::size_t>(std::max(size, 0)));
    check(MPI_Recv(message.data(), size, MPI_BYTE, status.MPI_SOURCE, kToRootTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE),
          "MPI_Recv");
    return message;
#else
    return std::nullopt;
#endif
}

std::vector<std::string> MpiSession::gatherProcesses() const {
    return gather(thisHostName() + ' ' + std::to_string(getpid()));
}

std::string thisHostName() {
    char host[256] = {};
    if (gethostname(host, sizeof host - 1) != 0) return {};
    return host;
}

std::string MpiSession::broadcast(const std::string& text) const {
#ifdef CVC_WITH_MPI
    if (!mIsStarted || mRanks == 1) return text;
    if (text.size() > static_cast<std::size_t>(std::numeric_limits<int>::max())) {
        throw std::invalid_argument("MPI: a broadcast of " + std::to_string(text.size()) + " bytes is too large");
    }
    unsigned long long size = text.size();
    check(MPI_Bcast(&size, 1, MPI_UNSIGNED_LONG_LONG, 0, MPI_COMM_WORLD), "MPI_Bcast");
    std::string received = mRank == 0 ? text : std::string(size, '\0');
    if (size > 0) {
        check(MPI_Bcast(received.data(), static_cast<int>(size), MPI_CHAR, 0, MPI_COMM_WORLD), "MPI_Bcast");
    }
    return received;
#else
    return text;
#endif
}

std::vector<std::string> MpiSession::gather(const std::string& text) const {
#ifdef CVC_WITH_MPI
    if (!mIsStarted || mRanks == 1) return {text};
    if (text.size() > static_cast<std::size_t>(std::numeric_limits<int>::max())) {
        throw std::invalid_argument("MPI: a gather of " + std::to_string(text.size()) + " bytes is too large");
    }
    const int size = static_cast<int>(text.size());
    std::vector<int> sizes(mRank == 0 ? static_cast<std::size_t>(mRanks) : 0);
    check(MPI_Gather(&size, 1, MPI_INT, sizes.data(), 1, MPI_INT, 0, MPI_COMM_WORLD), "MPI_Gather");
    std::vector<int> offsets(sizes.size());
    long long total = 0;
    for (std::size_t r = 0; r < sizes.size(); ++r) {
        if (total > std::numeric_limits<int>::max()) throw std::invalid_argument("MPI: the gathered text is too large");
        offsets[r] = static_cast<int>(total);
        total += sizes[r];
    }
    std::string all(static_cast<std::size_t>(total), '\0');
    check(MPI_Gatherv(text.data(), size, MPI_CHAR, all.data(), sizes.data(), offsets.data(), MPI_CHAR, 0,
                      MPI_COMM_WORLD),
          "MPI_Gatherv");
    std::vector<std::string> texts;
    for (std::size_t r = 0; r < sizes.size(); ++r) {
        texts.push_back(all.substr(static_cast<std::size_t>(offsets[r]), static_cast<std::size_t>(sizes[r])));
    }
    return texts;
#else
    return {text};
#endif
}

void MpiSession::abort(int code) const {
#ifdef CVC_WITH_MPI
    if (mIsStarted && mRanks > 1) MPI_Abort(MPI_COMM_WORLD, code);
#endif
    std::exit(code);
}

MpiSession& mpiSession() {
    static MpiSession alone;  // before main made one, or without it (a unit test)
    return gSession != nullptr ? *gSession : alone;
}

}  // namespace distribution
