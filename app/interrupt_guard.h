/// @brief Ctrl-C as a request to stop long work cleanly: while a guard lives, the first SIGINT
/// only sets a flag that the work polls (it then stops between frames and tidies up); a second
/// one stops the process at once.
#pragma once

namespace app {

class InterruptGuard {
public:
    /// Installs the handler and clears any earlier request; the destructor restores the handler
    /// that was there before.
    InterruptGuard();
    ~InterruptGuard();
    InterruptGuard(const InterruptGuard&) = delete;
    InterruptGuard& operator=(const InterruptGuard&) = delete;

    /// Whether Ctrl-C was pressed since the guard was made (safe from any thread).
    [[nodiscard]] static bool isRequested();

private:
    void (*mPrevious)(int);
};

}  // namespace app
