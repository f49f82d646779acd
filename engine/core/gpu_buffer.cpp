#include "engine/core/gpu_buffer.h"

#include <cstring>
#include <stdexcept>

namespace engine {

GpuBuffer::GpuBuffer(const GpuContext& context, vk::DeviceSize sizeBytes, vk::BufferUsageFlags usage, Memory memory,
                     const std::string& debugName)
    : mSizeBytes(sizeBytes),
      mBuffer(context.device(), vk::BufferCreateInfo({}, sizeBytes, usage, vk::SharingMode::eExclusive)) {
    const auto requirements = mBuffer.getMemoryRequirements();
    const auto properties = memory == Memory::HostVisible
                                ? vk::MemoryPropertyFlagBits::eHostVisible | vk::MemoryPropertyFlagBits::eHostCoherent
                                : vk::MemoryPropertyFlags(vk::MemoryPropertyFlagBits::eDeviceLocal);
    mMemory = context.allocateMemory(requirements, properties, debugName);
    mBuffer.bindMemory(*mMemory, 0);
    if (memory == Memory::HostVisible) mMapped = mMemory.mapMemory(0, VK_WHOLE_SIZE);
    context.setDebugName(mBuffer, debugName);
}

void GpuBuffer::write(std::span<const std::byte> bytes, vk::DeviceSize offset) {
    if (mMapped == nullptr) throw std::logic_error("GpuBuffer::write on a buffer that is not host-visible");
    if (offset > mSizeBytes || bytes.size() > mSizeBytes - offset) {
        throw std::out_of_range("GpuBuffer::write past the end of the buffer");
    }
    std::memcpy(static_cast<std::byte*>(mMapped) + offset, bytes.data(), bytes.size());
}

void GpuBuffer::read(std::span<std::byte> out, vk::DeviceSize offset) const {
    if (mMapped == nullptr) throw std::logic_error("GpuBuffer::read on a buffer that is not host-visible");
    if (offset > mSizeBytes || out.size() > mSizeBytes - offset) {
        throw std::out_of_range("GpuBuffer::read past the end of the buffer");
    }
    std::memcpy(out.data(), static_cast<const std::byte*>(mMapped) + offset, out.size());
}

}  // namespace engine
