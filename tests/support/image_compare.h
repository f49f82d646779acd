/// @brief Comparing two rendered images channel by channel.
#pragma once

#include <algorithm>
#include <cstdlib>
#include <utility>

#include "engine/render/raycaster.h"

namespace testing_support {

/// Largest difference of any colour channel between two images of one size, and the mean
/// difference over all channels.
inline std::pair<int, double> colorDifference(const engine::RenderedImage& a, const engine::RenderedImage& b) {
    int worst = 0;
    double sum = 0.0;
    for (std::size_t i = 0; i < a.rgba.size(); ++i) {
        const int d = std::abs(static_cast<int>(a.rgba[i]) - static_cast<int>(b.rgba[i]));
        worst = std::max(worst, d);
        sum += d;
    }
    return {worst, sum / static_cast<double>(a.rgba.size())};
}

}  // namespace testing_support
