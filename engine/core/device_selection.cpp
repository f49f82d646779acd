#include "engine/core/device_selection.h"

#include <algorithm>
#include <cctype>

namespace engine {
namespace {

int rankOf(DeviceCandidate::Kind kind) {
    switch (kind) {
        case DeviceCandidate::Kind::Discrete: return 0;
        case DeviceCandidate::Kind::Integrated: return 1;
        case DeviceCandidate::Kind::Virtual: return 2;
        case DeviceCandidate::Kind::Cpu: return 3;
        case DeviceCandidate::Kind::Other: return 4;
    }
    return 5;
}

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
    return s;
}

bool isDecimal(const std::string& s) {
    return !s.empty() && s.size() < 6 && std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isdigit(c); });
}

bool matchesPreference(const DeviceCandidate& candidate, std::size_t index, const std::string& preference) {
    const std::string wanted = lower(preference);
    if (isDecimal(wanted)) return std::stoul(wanted) == index;
    if (wanted == "cpu") return candidate.kind == DeviceCandidate::Kind::Cpu;
    if (wanted == "gpu") {
        return candidate.kind == DeviceCandidate::Kind::Discrete ||
               candidate.kind == DeviceCandidate::Kind::Integrated ||
               candidate.kind == DeviceCandidate::Kind::Virtual;
    }
    const std::string name = lower(candidate.name);
    // lavapipe reports itself as "llvmpipe": accept the driver's common name too.
    if (wanted == "lavapipe") return name.find("llvmpipe") != std::string::npos;
    return name.find(wanted) != std::string::npos;
}

}  // namespace

DeviceChoice chooseDevice(const std::vector<DeviceCandidate>& candidates, const std::string& preference) {
    DeviceChoice choice;
    if (candidates.empty()) {
        choice.explanation =
            "no Vulkan device found (on a machine without a GPU install Mesa's CPU driver "
            "lavapipe: apt-get install mesa-vulkan-drivers)";
        return choice;
    }
    std::string reasons;
    for (std::size_t i = 0; i < candidates.size(); ++i) {
        const DeviceCandidate& c = candidates[i];
        std::string reason = c.unusableReason;
        if (reason.empty() && !preference.empty() && !matchesPreference(c, i, preference)) {
            reason = "does not match the requested device '" + preference + "'";
        }
        if (!reason.empty()) {
            reasons += (reasons.empty() ? "" : "; ") + std::to_string(i) + " '" + c.name + "': " + reason;
            continue;
        }
        if (!choice.index || rankOf(c.kind) < rankOf(candidates[*choice.index].kind)) choice.index = i;
    }
    if (!choice.index) {
        choice.explanation = "no usable Vulkan device (" + reasons + ")";
    } else {
        choice.explanation = reasons;
    }
    return choice;
}

}  // namespace engine
