#include "engine/core/gpu_context.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <optional>

#include "engine/core/device_selection.h"

namespace engine {
namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";

bool environmentFlag(const char* name) {
    const char* value = std::getenv(name);
    return value != nullptr && std::strcmp(value, "0") != 0 && value[0] != '\0';
}

VKAPI_ATTR VkBool32 VKAPI_CALL onValidationMessage(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                   VkDebugUtilsMessageTypeFlagsEXT /*types*/,
                                                   const VkDebugUtilsMessengerCallbackDataEXT* data,
                                                   void* userData) {
    if ((severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) != 0 && data != nullptr) {
        static_cast<ValidationLog*>(userData)->add(data->pMessage != nullptr ? data->pMessage : "(no message)");
    }
    return VK_FALSE;
}

DeviceCandidate::Kind kindOf(vk::PhysicalDeviceType type) {
    switch (type) {
        case vk::PhysicalDeviceType::eDiscreteGpu: return DeviceCandidate::Kind::Discrete;
        case vk::PhysicalDeviceType::eIntegratedGpu: return DeviceCandidate::Kind::Integrated;
        case vk::PhysicalDeviceType::eVirtualGpu: return DeviceCandidate::Kind::Virtual;
        case vk::PhysicalDeviceType::eCpu: return DeviceCandidate::Kind::Cpu;
        default: return DeviceCandidate::Kind::Other;
    }
}

std::optional<uint32_t> computeQueueFamily(const vk::raii::PhysicalDevice& device) {
    const auto families = device.getQueueFamilyProperties();
    for (uint32_t i = 0; i < families.size(); ++i) {
        if (families[i].queueFlags & vk::QueueFlagBits::eCompute) return i;
    }
    return std::nullopt;
}

/// Why `device` cannot run the renderer, or "" when it can.
std::string unusableReason(const vk::raii::PhysicalDevice& device) {
    const auto properties = device.getProperties();
    if (properties.apiVersion < VK_API_VERSION_1_1) return "Vulkan 1.1 or newer is needed";
    if (!computeQueueFamily(device)) return "no compute queue";
    const auto volumeFormat = device.getFormatProperties(vk::Format::eR16Unorm);
    const auto needed = vk::FormatFeatureFlagBits::eSampledImage | vk::FormatFeatureFlagBits::eSampledImageFilterLinear;
    if ((volumeFormat.optimalTilingFeatures & needed) != needed) {
        return "R16_UNORM images cannot be sampled with linear filtering";
    }
    const auto colorFormat = device.getFormatProperties(vk::Format::eR8G8B8A8Unorm);
    if (!(colorFormat.optimalTilingFeatures & vk::FormatFeatureFlagBits::eStorageImage)) {
        return "R8G8B8A8_UNORM storage images are not supported";
    }
    // The cube map and the transfer function are sampled with linear filtering, the hit image
    // is written as a storage image, the empty-space map is read with texelFetch.
    if ((device.getFormatProperties(vk::Format::eR32G32B32A32Sfloat).optimalTilingFeatures & needed) != needed) {
        return "R32G32B32A32_SFLOAT images cannot be sampled with linear filtering";
    }
    if (!(device.getFormatProperties(vk::Format::eR32G32B32A32Sfloat).optimalTilingFeatures &
          vk::FormatFeatureFlagBits::eStorageImage)) {
        return "R32G32B32A32_SFLOAT storage images are not supported";
    }
    if ((device.getFormatProperties(vk::Format::eR16G16B16A16Unorm).optimalTilingFeatures & needed) != needed) {
        return "R16G16B16A16_UNORM images cannot be sampled with linear filtering";
    }
    if (!(device.getFormatProperties(vk::Format::eR8Uint).optimalTilingFeatures &
          vk::FormatFeatureFlagBits::eSampledImage)) {
        return "R8_UINT images cannot be sampled";
    }
    return {};
}

}  // namespace

void ValidationLog::add(std::string message) {
    std::lock_guard lock(mMutex);
    mErrors.push_back(std::move(message));
}

std::size_t ValidationLog::errorCount() const {
    std::lock_guard lock(mMutex);
    return mErrors.size();
}

std::vector<std::string> ValidationLog::errors() const {
    std::lock_guard lock(mMutex);
    return mErrors;
}

namespace {

/// "llvmpipe (LLVM 15.0.7, 256 bits), llvmpipe Mesa 25.0.7 (LLVM 19.1.7)": the device and the
/// driver's own name and version string (for Mesa, its version), from VkPhysicalDeviceDriverProperties
/// where the device has Vulkan 1.2; else the packed driver version number.
std::string driverDescriptionOf(const vk::raii::PhysicalDevice& device) {
    const auto properties = device.getProperties();
    std::string description = properties.deviceName.data();
    bool hasDriverProperties = properties.apiVersion >= VK_API_VERSION_1_2;
    for (const auto& extension : device.enumerateDeviceExtensionProperties()) {
        hasDriverProperties = hasDriverProperties ||
                              std::strcmp(extension.extensionName, VK_KHR_DRIVER_PROPERTIES_EXTENSION_NAME) == 0;
    }
    if (hasDriverProperties) {
        const auto chain = device.getProperties2<vk::PhysicalDeviceProperties2, vk::PhysicalDeviceDriverProperties>();
        const auto& driver = chain.get<vk::PhysicalDeviceDriverProperties>();
        return description + ", " + driver.driverName.data() + " " + driver.driverInfo.data();
    }
    return description + ", driver version " + std::to_string(properties.driverVersion);
}

}  // namespace

GpuContext::GpuContext(const GpuContextOptions& options)
    : mValidationLog(std::make_unique<ValidationLog>()),
      mIsValidationEnabled(options.enableValidation || environmentFlag("CVC_VALIDATION")) {
    // Instance: headless, no surface extensions. Debug utils gives validation messages and names.
    vk::ApplicationInfo appInfo("conformal-vc", 1, "conformal-vc", 1, VK_API_VERSION_1_1);
    std::vector<const char*> layers;
    std::vector<const char*> extensions;
    if (mIsValidationEnabled) {
        bool hasLayer = false;
        for (const auto& layer : mContext.enumerateInstanceLayerProperties()) {
            hasLayer = hasLayer || std::strcmp(layer.layerName, kValidationLayer) == 0;
        }
        if (!hasLayer) {
            throw NoDeviceError("validation was requested but the Vulkan validation layer is not "
                                "installed (apt-get install vulkan-validationlayers)");
        }
        layers.push_back(kValidationLayer);
        extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    }
    try {
        mInstance = vk::raii::Instance(mContext, vk::InstanceCreateInfo({}, &appInfo, layers, extensions));
    } catch (const vk::IncompatibleDriverError&) {
        throw NoDeviceError(
            "no Vulkan driver found (on a machine without a GPU install Mesa's CPU driver "
            "lavapipe: apt-get install mesa-vulkan-drivers)");
    }
    if (mIsValidationEnabled) {
        using Severity = vk::DebugUtilsMessageSeverityFlagBitsEXT;
        using Type = vk::DebugUtilsMessageTypeFlagBitsEXT;
        mMessenger = vk::raii::DebugUtilsMessengerEXT(
            mInstance, vk::DebugUtilsMessengerCreateInfoEXT({}, Severity::eError | Severity::eWarning,
                                                            Type::eGeneral | Type::eValidation | Type::ePerformance,
                                                            &onValidationMessage, mValidationLog.get()));
    }

    // Physical device: describe each, then let the (tested) selection logic choose.
    vk::raii::PhysicalDevices physicalDevices(mInstance);
    std::vector<DeviceCandidate> candidates;
    for (const auto& device : physicalDevices) {
        const auto properties = device.getProperties();
        candidates.push_back({properties.deviceName.data(), kindOf(properties.deviceType), unusableReason(device)});
    }
    std::string preference = options.devicePreference;
    if (preference.empty()) {
        if (const char* fromEnvironment = std::getenv(kDeviceEnvironmentVariable)) preference = fromEnvironment;
    }
    const DeviceChoice choice = chooseDevice(candidates, preference);
    if (!choice.index) throw NoDeviceError(choice.explanation);
    mPhysicalDevice = std::move(physicalDevices[*choice.index]);
    mDeviceName = candidates[*choice.index].name;
    mIsCpuDevice = candidates[*choice.index].kind == DeviceCandidate::Kind::Cpu;
    mQueueFamilyIndex = *computeQueueFamily(mPhysicalDevice);

    mDriverDescription = driverDescriptionOf(mPhysicalDevice);

    const auto families = mPhysicalDevice.getQueueFamilyProperties();
    if (families[mQueueFamilyIndex].timestampValidBits > 0) {
        mTimestampPeriodNs = mPhysicalDevice.getProperties().limits.timestampPeriod;
    }

    // Logical device with one compute queue.
    const float priority = 1.0f;
    vk::DeviceQueueCreateInfo queueInfo({}, mQueueFamilyIndex, 1, &priority);
    mDevice = vk::raii::Device(mPhysicalDevice, vk::DeviceCreateInfo({}, queueInfo));
    mQueue = vk::raii::Queue(mDevice, mQueueFamilyIndex, 0);
    mCommandPool = vk::raii::CommandPool(
        mDevice, vk::CommandPoolCreateInfo(vk::CommandPoolCreateFlagBits::eResetCommandBuffer, mQueueFamilyIndex));
}

uint32_t GpuContext::findMemoryType(uint32_t typeBits, vk::MemoryPropertyFlags properties) const {
    const auto memory = mPhysicalDevice.getMemoryProperties();
    for (uint32_t i = 0; i < memory.memoryTypeCount; ++i) {
        if ((typeBits & (1u << i)) && (memory.memoryTypes[i].propertyFlags & properties) == properties) return i;
    }
    throw std::runtime_error("no Vulkan memory type with the required properties on " + mDeviceName);
}

vk::DeviceSize GpuContext::largestAllocationBytes(vk::MemoryPropertyFlags properties) const {
    const auto memory = mPhysicalDevice.getMemoryProperties();
    const uint32_t type = findMemoryType(~0u, properties);
    const vk::DeviceSize heapBytes = memory.memoryHeaps[memory.memoryTypes[type].heapIndex].size;
    // Vulkan 1.1 (which the context requires) reports the largest single allocation.
    const auto chain = mPhysicalDevice.getProperties2<vk::PhysicalDeviceProperties2, vk::PhysicalDeviceMaintenance3Properties>();
    const vk::DeviceSize allocationBytes = chain.get<vk::PhysicalDeviceMaintenance3Properties>().maxMemoryAllocationSize;
    return allocationBytes > 0 ? std::min(heapBytes, allocationBytes) : heapBytes;
}

std::string mebibytesText(vk::DeviceSize bytes) {
    return std::to_string((bytes + (1u << 20) - 1) >> 20) + " MiB";
}

vk::raii::DeviceMemory GpuContext::allocateMemory(const vk::MemoryRequirements& requirements,
                                                  vk::MemoryPropertyFlags properties, const std::string& what) const {
    const vk::DeviceSize largest = largestAllocationBytes(properties);
    if (requirements.size > largest) {
        throw DeviceMemoryError(what + " needs " + mebibytesText(requirements.size) +
                                    " in one allocation, more than the " + mebibytesText(largest) + " that " +
                                    mDeviceName + " allows",
                                largest);
    }
    try {
        return vk::raii::DeviceMemory(
            mDevice, vk::MemoryAllocateInfo(requirements.size, findMemoryType(requirements.memoryTypeBits, properties)));
    } catch (const vk::OutOfDeviceMemoryError&) {
        throw DeviceMemoryError(
            what + ": " + mDeviceName + " has not " + mebibytesText(requirements.size) + " of memory free", largest);
    } catch (const vk::OutOfHostMemoryError&) {
        throw DeviceMemoryError(what + ": the host has not " + mebibytesText(requirements.size) + " of memory free",
                                largest);
    }
}

void GpuContext::setDebugNameRaw(vk::ObjectType type, uint64_t handle, const std::string& name) const {
    if (!mIsValidationEnabled) return;  // debug utils is only enabled alongside validation
    mDevice.setDebugUtilsObjectNameEXT(vk::DebugUtilsObjectNameInfoEXT(type, handle, name.c_str()));
}

}  // namespace engine
