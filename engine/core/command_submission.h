/// @brief Recording a command buffer, submitting it and waiting for it; device timestamps.
#pragma once

#include <chrono>
#include <functional>

#include "engine/core/gpu_context.h"

namespace engine {

/// Work recorded into a one-time command buffer and submitted, which the host may wait for
/// later: it can prepare or post-process other work meanwhile. Waits in its destructor too (a
/// command buffer must outlive its execution), so dropping it is always safe.
class SubmittedWork {
public:
    SubmittedWork(const GpuContext& context, const std::function<void(const vk::raii::CommandBuffer&)>& record);
    ~SubmittedWork();
    SubmittedWork(SubmittedWork&&) noexcept = default;
    SubmittedWork& operator=(SubmittedWork&&) = delete;
    SubmittedWork(const SubmittedWork&) = delete;
    SubmittedWork& operator=(const SubmittedWork&) = delete;

    /// Blocks until the device finished; throws if it does not within `timeout` (a hung device
    /// becomes an error, not a hung program). Returns at once when already waited for.
    void wait(std::chrono::seconds timeout = std::chrono::seconds(600));

private:
    const GpuContext* mContext;
    vk::raii::CommandBuffers mCommands;
    vk::raii::Fence mFence;
    bool mIsFinished = false;
};

/// Records commands with `record` into a fresh one-time command buffer, submits it to the
/// context's queue and blocks until it finished. Throws if the device does not finish within
/// `timeout` (a hung device becomes an error, not a hung program).
void submitAndWait(const GpuContext& context, const std::function<void(const vk::raii::CommandBuffer&)>& record,
                   std::chrono::seconds timeout = std::chrono::seconds(600));

/// Two timestamps around recorded work, read after the submission finished.
class GpuTimer {
public:
    explicit GpuTimer(const GpuContext& context);
    void recordStart(const vk::raii::CommandBuffer& commands) const;
    void recordEnd(const vk::raii::CommandBuffer& commands) const;
    /// Device time between the two timestamps in milliseconds; negative when the queue has no
    /// timestamp support.
    [[nodiscard]] double elapsedMs() const;

private:
    const GpuContext* mContext;
    vk::raii::QueryPool mPool;
};

}  // namespace engine
