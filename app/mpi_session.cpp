#include "app/mpi_session.h"

#include <algorithm>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#ifdef CVC_WITH_MPI
#include <mpi.h>
#endif

namespace app {
namespace {

const MpiSession* gSession = nullptr;

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

int MpiSession::threadsPerRank(int cores, int ranksOnMachine) {
    return std::max(1, std::max(cores, 1) / std::max(ranksOnMachine, 1));
}

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
    if (mIsStarted) MPI_Finalize();
#endif
    if (gSession == this) gSession = nullptr;
}

void MpiSession::barrier() const {
#ifdef CVC_WITH_MPI
    if (mIsStarted) check(MPI_Barrier(MPI_COMM_WORLD), "MPI_Barrier");
#endif
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

const MpiSession& mpiSession() {
    static const MpiSession alone;  // before main made one, or without it (a unit test)
    return gSession != nullptr ? *gSession : alone;
}

}  // namespace app
