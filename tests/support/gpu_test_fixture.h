/// @brief A GoogleTest fixture that shares one validated Vulkan context across a suite and
/// fails any test during which the validation layer reported an error.
#pragma once

#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "engine/core/gpu_context.h"

namespace testing_support {

class GpuTest : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        if (sContext || !sSkipReason.empty()) return;
        try {
            sContext = std::make_unique<engine::GpuContext>(engine::GpuContextOptions{true, ""});
        } catch (const engine::NoDeviceError& e) {
            sSkipReason = e.what();
        }
    }

    void SetUp() override {
        if (!sContext) GTEST_SKIP() << "no Vulkan device: " << sSkipReason;
        mErrorsBefore = sContext->validationLog().errorCount();
    }

    void TearDown() override {
        if (!sContext) return;
        const auto errors = sContext->validationLog().errors();
        for (std::size_t i = mErrorsBefore; i < errors.size(); ++i) ADD_FAILURE() << "validation error: " << errors[i];
    }

    static const engine::GpuContext& context() { return *sContext; }

private:
    static inline std::unique_ptr<engine::GpuContext> sContext;
    static inline std::string sSkipReason;
    std::size_t mErrorsBefore = 0;
};

}  // namespace testing_support
