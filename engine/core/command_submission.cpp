#include "engine/core/command_submission.h"

#include <array>
#include <stdexcept>

namespace engine {

SubmittedWork::SubmittedWork(const GpuContext& context, const std::function<void(const vk::raii::CommandBuffer&)>& record)
    : mContext(&context),
      mCommands(context.device(),
                vk::CommandBufferAllocateInfo(*context.commandPool(), vk::CommandBufferLevel::ePrimary, 1)),
      mFence(context.device(), vk::FenceCreateInfo()) {
    const vk::raii::CommandBuffer& commands = mCommands.front();
    commands.begin(vk::CommandBufferBeginInfo(vk::CommandBufferUsageFlagBits::eOneTimeSubmit));
    record(commands);
    commands.end();
    vk::CommandBuffer handle = *commands;
    context.queue().submit(vk::SubmitInfo({}, {}, handle), *mFence);
}

SubmittedWork::~SubmittedWork() {
    if (mIsFinished || mCommands.empty()) return;  // waited for, or moved from
    // A command buffer must not be destroyed while it executes, so wait, but within the same
    // limit as wait(): a device that has not finished in 10 minutes is hung, and a hung program
    // helps nobody. A failure here has nowhere to go (a destructor must not throw).
    try {
        const vk::Result ignored = mContext->device().waitForFences(*mFence, VK_TRUE, 600'000'000'000ull);
        (void)ignored;
    } catch (const vk::SystemError&) {
    }
}

void SubmittedWork::wait(std::chrono::seconds timeout) {
    if (mIsFinished) return;
    const auto timeoutNs = static_cast<uint64_t>(std::chrono::nanoseconds(timeout).count());
    const vk::Result waited = mContext->device().waitForFences(*mFence, VK_TRUE, timeoutNs);
    if (waited != vk::Result::eSuccess) {
        throw std::runtime_error("the Vulkan device did not finish the work within " +
                                 std::to_string(timeout.count()) + " s (" + vk::to_string(waited) + ")");
    }
    mIsFinished = true;
}

void submitAndWait(const GpuContext& context, const std::function<void(const vk::raii::CommandBuffer&)>& record,
                   std::chrono::seconds timeout) {
    SubmittedWork work(context, record);
    work.wait(timeout);
}

GpuTimer::GpuTimer(const GpuContext& context)
    : mContext(&context),
      mPool(context.device(), vk::QueryPoolCreateInfo({}, vk::QueryType::eTimestamp, 2)) {}

void GpuTimer::recordStart(const vk::raii::CommandBuffer& commands) const {
    commands.resetQueryPool(*mPool, 0, 2);
    commands.writeTimestamp(vk::PipelineStageFlagBits::eTopOfPipe, *mPool, 0);
}

void GpuTimer::recordEnd(const vk::raii::CommandBuffer& commands) const {
    commands.writeTimestamp(vk::PipelineStageFlagBits::eBottomOfPipe, *mPool, 1);
}

double GpuTimer::elapsedMs() const {
    if (mContext->timestampPeriodNs() <= 0.0) return -1.0;
    const auto [result, ticks] = mPool.getResults<uint64_t>(0, 2, 2 * sizeof(uint64_t), sizeof(uint64_t),
                                                              vk::QueryResultFlagBits::e64 | vk::QueryResultFlagBits::eWait);
    if (result != vk::Result::eSuccess) return -1.0;
    return static_cast<double>(ticks[1] - ticks[0]) * mContext->timestampPeriodNs() * 1e-6;
}

}  // namespace engine
