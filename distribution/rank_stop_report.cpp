#include "distribution/rank_stop_report.h"

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <utility>

#include <sys/stat.h>
#include <unistd.h>

#include "engine/sequence/frame_sequence.h"

namespace distribution {
namespace {

/// Text into a fixed buffer, always zero-terminated, cut at its end: what a signal handler may
/// build (no allocation, no locale, no stdio).
class FixedText {
public:
    FixedText(char* buffer, std::size_t size) : mBuffer(buffer), mSize(size) {
        if (mSize > 0) mBuffer[0] = '\0';
    }
    FixedText& operator<<(const char* text) {
        for (; text != nullptr && *text != '\0'; ++text) put(*text);
        return *this;
    }
    FixedText& operator<<(const std::string& text) { return *this << text.c_str(); }
    FixedText& operator<<(char c) {
        put(c);
        return *this;
    }
    FixedText& operator<<(long value) {
        char digits[24];
        int count = 0;
        const bool isNegative = value < 0;
        // The magnitude in unsigned arithmetic, so that the most negative long has one too.
        unsigned long magnitude = static_cast<unsigned long>(value);
        if (isNegative) magnitude = 0UL - magnitude;
        do {
            digits[count++] = static_cast<char>('0' + magnitude % 10);
            magnitude /= 10;
        } while (magnitude != 0 && count < 23);
        if (isNegative) put('-');
        while (count > 0) put(digits[--count]);
        return *this;
    }
    FixedText& operator<<(int value) { return *this << static_cast<long>(value); }
    [[nodiscard]] std::size_t length() const { return mLength; }

private:
    void put(char c) {
        if (mLength + 1 >= mSize) return;
        mBuffer[mLength++] = c;
        mBuffer[mLength] = '\0';
    }
    char* mBuffer;
    std::size_t mSize;
    std::size_t mLength = 0;
};

bool isFolder(const std::string& path) {
    struct stat status {};
    return ::stat(path.c_str(), &status) == 0 && S_ISDIR(status.st_mode);
}

/// A rank ran on this machine and its process is gone (mpirun reaps a dead rank before it
/// stops the others, so a killed one is no longer there, not even as a zombie).
bool hasEnded(const RankStopState& state, const RankProcess& process) {
    return process.pid > 0 && process.host == state.host && ::kill(static_cast<pid_t>(process.pid), 0) != 0 &&
           errno == ESRCH;
}

bool isFinished(const RankStopState& state, int frame) {
    return frame >= 0 && static_cast<std::size_t>(frame) < state.finishedPaths.size() &&
           isFolder(state.finishedPaths[static_cast<std::size_t>(frame)]);
}

bool isWrittenOrFinished(const RankStopState& state, int frame) {
    return isFinished(state, frame) || (static_cast<std::size_t>(frame) < state.writtenPaths.size() &&
                                        isFolder(state.writtenPaths[static_cast<std::size_t>(frame)]));
}

/// The first of rank `rank`'s frames it had not written, or -1 when it wrote them all.
int frameAt(const RankStopState& state, std::size_t rank) {
    if (rank >= state.frames.size()) return -1;
    for (int frame : state.frames[rank]) {
        if (!isWrittenOrFinished(state, frame)) return frame;
    }
    return -1;
}

/// "<atWord> frame 7" ("at frame 7", "while at frame 7"), or "after writing all its frames".
void describeRankAt(FixedText& text, const RankStopState& state, std::size_t rank, const char* atWord) {
    const int frame = frameAt(state, rank);
    if (frame >= 0) {
        text << atWord << " frame " << frame;
    } else {
        text << "after writing all its frames";
    }
}

RankStopReport* gReport = nullptr;

}  // namespace

std::vector<RankProcess> rankProcessesOf(const std::vector<std::string>& texts) {
    std::vector<RankProcess> processes;
    for (const std::string& text : texts) {
        RankProcess process;
        const std::size_t space = text.rfind(' ');
        if (space != std::string::npos) {
            process.host = text.substr(0, space);
            char* end = nullptr;
            const long pid = std::strtol(text.c_str() + space + 1, &end, 10);
            if (end != nullptr && *end == '\0' && pid > 0) process.pid = pid;
        }
        processes.push_back(process);
    }
    return processes;
}

RankStopState rankStopStateOf(const std::string& folder, const std::string& host,
                              std::vector<RankProcess> processes, std::vector<std::vector<int>> frames,
                              int framesTotal) {
    RankStopState state;
    state.folder = folder;
    state.host = host;
    state.processes = std::move(processes);
    state.frames = std::move(frames);
    state.framesTotal = std::max(framesTotal, 0);
    for (int i = 0; i < state.framesTotal; ++i) {
        state.finishedPaths.push_back(folder + "/" + engine::frameFolderName(i));
        state.writtenPaths.push_back(folder + "/" + engine::writtenFrameFolderName(i));
    }
    return state;
}

std::size_t composeRankStopReport(const RankStopState& state, char* buffer, std::size_t size) {
    FixedText text(buffer, size);
    text << "cvc: error: ";
    bool isAnyEnded = false;
    for (std::size_t rank = 0; rank < state.processes.size(); ++rank) {
        if (!hasEnded(state, state.processes[rank])) continue;
        text << (isAnyEnded ? "; " : "") << "rank " << static_cast<long>(rank) << " (pid "
             << state.processes[rank].pid << ") ended ";
        describeRankAt(text, state, rank, "while at");
        isAnyEnded = true;
    }
    if (isAnyEnded) {
        text << ", so mpirun is stopping the job";
    } else {
        text << "the job was stopped (SIGTERM: mpirun ends the job when a rank ends on another machine, or when it is "
                "cancelled) with ";
        for (std::size_t rank = 0; rank < state.frames.size(); ++rank) {
            text << (rank > 0 ? ", " : "") << "rank " << static_cast<long>(rank) << ' ';
            describeRankAt(text, state, rank, "at");
        }
    }
    // A frame another rank wrote whole is kept too: resuming writes its sheet from its images.
    int finished = 0;
    int waitingForSheet = 0;
    for (int frame = 0; frame < state.framesTotal; ++frame) {
        finished += isWrittenOrFinished(state, frame) ? 1 : 0;
        waitingForSheet += isWrittenOrFinished(state, frame) && !isFinished(state, frame) ? 1 : 0;
    }
    text << ". " << finished << " of " << state.framesTotal << " frames are finished in " << state.folder
         << " and kept";
    if (waitingForSheet > 0) text << " (" << waitingForSheet << " with every image, waiting only for the sheet)";
    text << ": run the same command with --resume (any number of ranks) to render the rest.\n";
    return text.length();
}

RankStopReport::RankStopReport(bool isOnTerminal) : mIsOnTerminal(isOnTerminal) {
    gReport = this;
    struct sigaction action {};
    action.sa_handler = &RankStopReport::onTerminate;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESETHAND;  // a second SIGTERM ends the process at once
    sigaction(SIGTERM, &action, &mPrevious);
}

RankStopReport::~RankStopReport() {
    sigaction(SIGTERM, &mPrevious, nullptr);
    gReport = nullptr;
}

void RankStopReport::arm(RankStopState state) {
    if (mIsArmed.load()) return;
    mState = std::move(state);
    mIsArmed.store(true, std::memory_order_release);
}

void RankStopReport::onTerminate(int signal) {
    const int savedErrno = errno;
    static char report[4096];
    std::size_t length = 0;
    const RankStopReport* self = gReport;
    if (self != nullptr && self->mIsArmed.load(std::memory_order_acquire)) {
        length = composeRankStopReport(self->mState, report, sizeof report);
    } else {
        FixedText text(report, sizeof report);
        text << "cvc: error: the job was stopped (SIGTERM) before its frames were dealt out\n";
        length = text.length();
    }
    if (self != nullptr && self->mIsOnTerminal) (void)!::write(STDERR_FILENO, "\n", 1);
    for (std::size_t written = 0; written < length;) {
        const ssize_t n = ::write(STDERR_FILENO, report + written, length - written);
        if (n <= 0) break;
        written += static_cast<std::size_t>(n);
    }
    errno = savedErrno;
    // SA_RESETHAND put the default action back: end as SIGTERM would have.
    ::raise(signal);
}

}  // namespace distribution
