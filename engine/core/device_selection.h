/// @brief Choosing the Vulkan physical device: pure logic, testable without a driver.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace engine {

/// What the selector needs to know of one physical device.
struct DeviceCandidate {
    std::string name;
    enum class Kind { Discrete, Integrated, Virtual, Cpu, Other } kind = Kind::Other;
    /// Empty when the device can run the renderer; otherwise why it cannot.
    std::string unusableReason;
};

/// Result of a selection: the chosen index, or why nothing was chosen.
struct DeviceChoice {
    std::optional<std::size_t> index;
    std::string explanation;  // one line: the reasons each device was passed over
};

/// Picks a device. With an empty `preference`, the best usable kind wins (discrete, then
/// integrated, virtual, CPU such as lavapipe); ties go to the first enumerated. A non-empty
/// `preference` forces a device: a decimal index into `candidates`, or a case-insensitive
/// part of its name ("lavapipe", "llvmpipe", "nvidia"); "cpu" and "gpu" select by kind.
DeviceChoice chooseDevice(const std::vector<DeviceCandidate>& candidates, const std::string& preference);

/// Name of the environment variable read when no --device is given.
inline constexpr const char* kDeviceEnvironmentVariable = "CVC_DEVICE";

}  // namespace engine
