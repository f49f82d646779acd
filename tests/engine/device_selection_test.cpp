#include "engine/core/device_selection.h"

#include <gtest/gtest.h>

namespace {

using engine::chooseDevice;
using engine::DeviceCandidate;
using Kind = DeviceCandidate::Kind;

const std::vector<DeviceCandidate> kMachine = {
    {"llvmpipe (LLVM 15.0.6, 256 bits)", Kind::Cpu, ""},
    {"NVIDIA H100", Kind::Discrete, ""},
    {"Intel(R) UHD Graphics", Kind::Integrated, ""},
};

TEST(DeviceSelection, PrefersDiscreteThenIntegratedThenCpu) {
    EXPECT_EQ(chooseDevice(kMachine, "").index, 1u);
    EXPECT_EQ(chooseDevice({kMachine[0], kMachine[2]}, "").index, 1u);
    EXPECT_EQ(chooseDevice({kMachine[0]}, "").index, 0u);
}

TEST(DeviceSelection, PreferenceForcesByNameIndexOrKind) {
    EXPECT_EQ(chooseDevice(kMachine, "lavapipe").index, 0u);
    EXPECT_EQ(chooseDevice(kMachine, "LLVMPIPE").index, 0u);
    EXPECT_EQ(chooseDevice(kMachine, "intel").index, 2u);
    EXPECT_EQ(chooseDevice(kMachine, "2").index, 2u);
    EXPECT_EQ(chooseDevice(kMachine, "cpu").index, 0u);
    EXPECT_EQ(chooseDevice(kMachine, "gpu").index, 1u);
}

TEST(DeviceSelection, ExplainsWhyNothingWasChosen) {
    const auto none = chooseDevice(kMachine, "amd");
    EXPECT_FALSE(none.index);
    EXPECT_NE(none.explanation.find("does not match the requested device 'amd'"), std::string::npos);
    EXPECT_NE(none.explanation.find("NVIDIA H100"), std::string::npos);

    const auto empty = chooseDevice({}, "");
    EXPECT_FALSE(empty.index);
    EXPECT_NE(empty.explanation.find("mesa-vulkan-drivers"), std::string::npos);
}

TEST(DeviceSelection, SkipsUnusableDevices) {
    std::vector<DeviceCandidate> machine = kMachine;
    machine[1].unusableReason = "no compute queue";
    const auto choice = chooseDevice(machine, "");
    EXPECT_EQ(choice.index, 2u);
    EXPECT_NE(choice.explanation.find("no compute queue"), std::string::npos);
    EXPECT_FALSE(chooseDevice(machine, "nvidia").index);
}

}  // namespace
