#include "app/progress_bar.h"

#include <cmath>
#include <cstdio>
#include <iomanip>
#include <sstream>
#include <string>

namespace app {
namespace {

std::string clock(double seconds) {
    const long total = std::lround(std::max(seconds, 0.0));
    std::ostringstream text;
    text << total / 3600 << ':' << std::setw(2) << std::setfill('0') << (total / 60) % 60 << ':' << std::setw(2)
         << std::setfill('0') << total % 60;
    return text.str();
}

}  // namespace

ProgressBar::ProgressBar(std::ostream& out, int total, int alreadyDone, bool isTerminal)
    : mOut(out), mTotal(total), mStartDone(alreadyDone), mIsTerminal(isTerminal), mStart(std::chrono::steady_clock::now()) {}

void ProgressBar::update(int done) {
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - mStart).count();
    const int renderedNow = done - mStartDone;
    const double perMinute = renderedNow > 0 && elapsed > 0.0 ? 60.0 * renderedNow / elapsed : 0.0;
    const double left = perMinute > 0.0 ? 60.0 * (mTotal - done) / perMinute : 0.0;
    constexpr int kWidth = 30;
    const int filled = mTotal > 0 ? kWidth * done / mTotal : kWidth;
    std::ostringstream line;
    line << "frames " << done << '/' << mTotal << " [";
    for (int i = 0; i < kWidth; ++i) line << (i < filled ? '#' : '.');
    line << "] " << std::fixed << std::setprecision(1) << perMinute << " frames/min, " << clock(left) << " left";
    if (mIsTerminal) {
        mOut << '\r' << line.str() << "   " << std::flush;
    } else {
        mOut << line.str() << '\n' << std::flush;
    }
}

void ProgressBar::finish() {
    if (mIsTerminal) mOut << '\n' << std::flush;
}

}  // namespace app
