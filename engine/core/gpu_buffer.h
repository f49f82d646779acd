/// @brief A Vulkan buffer with its own memory: host-visible (mapped) for uploads and
/// readbacks, or device-local for data the shaders read.
#pragma once

#include <span>
#include <string>

#include "engine/core/gpu_context.h"

namespace engine {

class GpuBuffer {
public:
    enum class Memory { HostVisible, DeviceLocal };

    GpuBuffer(const GpuContext& context, vk::DeviceSize sizeBytes, vk::BufferUsageFlags usage, Memory memory,
              const std::string& debugName);

    [[nodiscard]] const vk::raii::Buffer& buffer() const { return mBuffer; }
    [[nodiscard]] vk::DeviceSize sizeBytes() const { return mSizeBytes; }
    /// Host address of the contents; only for Memory::HostVisible (host-coherent) buffers.
    [[nodiscard]] void* mapped() const { return mMapped; }

    /// Copies `bytes` into a host-visible buffer at `offset`; throws if it does not fit.
    void write(std::span<const std::byte> bytes, vk::DeviceSize offset = 0);
    /// Copies `out.size()` bytes out of a host-visible buffer at `offset`.
    void read(std::span<std::byte> out, vk::DeviceSize offset = 0) const;

private:
    vk::DeviceSize mSizeBytes;
    vk::raii::Buffer mBuffer;
    vk::raii::DeviceMemory mMemory{nullptr};
    void* mMapped = nullptr;  // owned by mMemory; unmapped when it is freed
};

}  // namespace engine
