/// @brief A progress line for long renders: frames done, frames per minute, time left.
#pragma once

#include <chrono>
#include <ostream>

namespace app {

/// On a terminal the line redraws itself in place; in a log (CI, a pipe) it prints one line
/// per update, so nothing is lost.
class ProgressBar {
public:
    ProgressBar(std::ostream& out, int total, int alreadyDone, bool isTerminal);
    /// Reports that `done` of the total frames are finished.
    void update(int done);
    /// Ends the line.
    void finish();

private:
    std::ostream& mOut;
    int mTotal;
    int mStartDone;
    bool mIsTerminal;
    std::chrono::steady_clock::time_point mStart;
};

}  // namespace app
