/// @brief Recording a command buffer, submitting it and waiting for it; device timestamps.
#pragma once

#include <chrono>
#include <functional>

#include "engine/gpu_context.h"

namespace engine {

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
