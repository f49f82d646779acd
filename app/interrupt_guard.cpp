#include "app/interrupt_guard.h"

#include <atomic>
#include <csignal>

namespace app {
namespace {

std::atomic<bool> gInterruptRequested{false};

extern "C" void onInterrupt(int) {
    gInterruptRequested = true;
    std::signal(SIGINT, SIG_DFL);  // a second Ctrl-C stops at once
}

}  // namespace

InterruptGuard::InterruptGuard() : mPrevious(std::signal(SIGINT, onInterrupt)) { gInterruptRequested = false; }

InterruptGuard::~InterruptGuard() { std::signal(SIGINT, mPrevious); }

bool InterruptGuard::isRequested() { return gInterruptRequested.load(); }

}  // namespace app
