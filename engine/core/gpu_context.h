/// @brief The headless Vulkan instance, physical and logical device, compute queue and
/// command pool that every GPU resource of the program hangs off.
#pragma once

#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include <vulkan/vulkan_raii.hpp>

namespace engine {

/// No Vulkan driver or no device that can run the renderer; the message says why.
class NoDeviceError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// How to set the device up.
struct GpuContextOptions {
    /// Turn on the Khronos validation layer and record what it reports (tests do; a missing
    /// layer is then an error). Also switched on by the environment variable CVC_VALIDATION=1.
    bool enableValidation = false;
    /// Forces a device (see chooseDevice); empty: the CVC_DEVICE variable, else the best one.
    std::string devicePreference;
};

/// Messages of severity "error" reported by the validation layer, kept for tests to assert on.
class ValidationLog {
public:
    void add(std::string message);
    [[nodiscard]] std::size_t errorCount() const;
    [[nodiscard]] std::vector<std::string> errors() const;

private:
    mutable std::mutex mMutex;
    std::vector<std::string> mErrors;
};

/// `bytes` as whole MiB, rounded up ("3 MiB"), for messages about device memory.
std::string mebibytesText(vk::DeviceSize bytes);

/// Device memory that cannot be had: more than the device allows in one allocation, or more than
/// it has free. `largestBytes` is what one allocation may have, for a message saying what would fit.
class DeviceMemoryError : public std::runtime_error {
public:
    DeviceMemoryError(const std::string& message, vk::DeviceSize largestBytes)
        : std::runtime_error(message), mLargestBytes(largestBytes) {}
    [[nodiscard]] vk::DeviceSize largestBytes() const { return mLargestBytes; }

private:
    vk::DeviceSize mLargestBytes;
};

/// Owns the Vulkan objects in creation order, so they are destroyed in reverse.
/// Every Vulkan call goes through vulkan_raii.hpp, which throws vk::SystemError (carrying the
/// VkResult and the call's name) on any failure.
class GpuContext {
public:
    explicit GpuContext(const GpuContextOptions& options = {});

    GpuContext(const GpuContext&) = delete;
    GpuContext& operator=(const GpuContext&) = delete;

    [[nodiscard]] const vk::raii::Device& device() const { return mDevice; }
    [[nodiscard]] const vk::raii::PhysicalDevice& physicalDevice() const { return mPhysicalDevice; }
    [[nodiscard]] const vk::raii::Queue& queue() const { return mQueue; }
    [[nodiscard]] const vk::raii::CommandPool& commandPool() const { return mCommandPool; }
    [[nodiscard]] uint32_t queueFamilyIndex() const { return mQueueFamilyIndex; }
    [[nodiscard]] const std::string& deviceName() const { return mDeviceName; }
    [[nodiscard]] bool isCpuDevice() const { return mIsCpuDevice; }
    /// The device with its driver's name and version, e.g. "llvmpipe (LLVM 19.1.7, 256 bits),
    /// llvmpipe Mesa 25.0.7 (LLVM 19.1.7)": what a benchmark or a manifest records.
    [[nodiscard]] const std::string& driverDescription() const { return mDriverDescription; }
    /// Nanoseconds per timestamp tick; 0 when the queue has no timestamps.
    [[nodiscard]] double timestampPeriodNs() const { return mTimestampPeriodNs; }
    [[nodiscard]] const ValidationLog& validationLog() const { return *mValidationLog; }
    [[nodiscard]] bool isValidationEnabled() const { return mIsValidationEnabled; }

    /// Index of a memory type allowed by `typeBits` with all `properties`; throws if none.
    [[nodiscard]] uint32_t findMemoryType(uint32_t typeBits, vk::MemoryPropertyFlags properties) const;

    /// The most bytes one allocation of memory with `properties` may have on this device: the
    /// smaller of its heap and the driver's maxMemoryAllocationSize (2 GiB on lavapipe).
    [[nodiscard]] vk::DeviceSize largestAllocationBytes(vk::MemoryPropertyFlags properties) const;

    /// Memory for `requirements` with `properties`. A request larger than largestAllocationBytes,
    /// or one the driver cannot satisfy, throws DeviceMemoryError naming `what`, the bytes asked
    /// and the bytes the device allows, instead of a bare VkResult.
    [[nodiscard]] vk::raii::DeviceMemory allocateMemory(const vk::MemoryRequirements& requirements,
                                                        vk::MemoryPropertyFlags properties, const std::string& what) const;

    /// Gives a Vulkan object a name that validation messages then use instead of a handle.
    template <typename Handle>
    void setDebugName(const Handle& handle, const std::string& name) const {
        setDebugNameRaw(Handle::objectType, reinterpret_cast<uint64_t>(static_cast<typename Handle::CType>(*handle)), name);
    }

private:
    void setDebugNameRaw(vk::ObjectType type, uint64_t handle, const std::string& name) const;

    std::unique_ptr<ValidationLog> mValidationLog;  // stable address for the layer's callback
    bool mIsValidationEnabled = false;
    vk::raii::Context mContext;
    vk::raii::Instance mInstance{nullptr};
    vk::raii::DebugUtilsMessengerEXT mMessenger{nullptr};
    vk::raii::PhysicalDevice mPhysicalDevice{nullptr};
    uint32_t mQueueFamilyIndex = 0;
    vk::raii::Device mDevice{nullptr};
    vk::raii::Queue mQueue{nullptr};
    vk::raii::CommandPool mCommandPool{nullptr};
    std::string mDeviceName;
    std::string mDriverDescription;
    bool mIsCpuDevice = false;
    double mTimestampPeriodNs = 0.0;
};

}  // namespace engine
