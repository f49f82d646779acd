// The render settings are a seam free of Vulkan: option parsing, manifests and the display
// pipeline build them without the ray caster. Their ranges are checked in one place.
#include "engine/render/render_settings.h"

// Included first and alone: if it pulled in a Vulkan header, these guards would be defined.
#if defined(VULKAN_CORE_H_) || defined(VULKAN_HPP) || defined(VULKAN_RAII_HPP)
#error "engine/render/render_settings.h includes Vulkan"
#endif

#include <cmath>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

namespace {

/// The message validateRenderSettings throws for `settings`, or "" when it accepts them.
std::string refusalOf(const engine::RenderSettings& settings) {
    try {
        engine::validateRenderSettings(settings);
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "";
}

TEST(RenderSettings, DefaultsAreValid) { EXPECT_EQ(refusalOf(engine::RenderSettings{}), ""); }

TEST(RenderSettings, EachSettingOutsideItsRangeIsRefusedByName) {
    const auto refused = [](auto change, const std::string& named) {
        engine::RenderSettings settings;
        change(settings);
        const std::string message = refusalOf(settings);
        EXPECT_NE(message.find(named), std::string::npos) << "got: '" << message << "'";
    };
    refused([](engine::RenderSettings& s) { s.stepVoxels = 0.0; }, "step");
    refused([](engine::RenderSettings& s) { s.stepVoxels = 9.0; }, "step");
    refused([](engine::RenderSettings& s) { s.skipCellVoxels = 0; }, "skipping cells");
    refused([](engine::RenderSettings& s) { s.refinementSteps = 33; }, "refinement steps");
    refused([](engine::RenderSettings& s) { s.isoHu = std::nan(""); }, "iso value");
    refused([](engine::RenderSettings& s) { s.minStepVoxels = 5.0; }, "adaptive step bounds");
    refused([](engine::RenderSettings& s) { s.earlyTerminationOpacity = 0.0; }, "early termination");
    refused([](engine::RenderSettings& s) { s.lightHalfDistanceMm = -1.0; }, "light half distance");
    refused([](engine::RenderSettings& s) { s.roughness = 0.0; }, "roughness");
}

}  // namespace
