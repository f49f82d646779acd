/// @brief How far apart two renders of the same view are, as the benchmarks report it beside
/// their times: the largest colour-channel difference and the share of pixels more than 2
/// levels apart.
#pragma once

#include <algorithm>
#include <cstdlib>
#include <stdexcept>

#include "engine/render/render_settings.h"

namespace bench {

struct ImageDifference {
    int largestChannel = 0;
    std::size_t pixels = 0;
    std::size_t pixelsOver2Levels = 0;

    /// Adds the pixels of two RGBA renders of one size (alpha, always opaque, is not compared).
    void add(const engine::RenderedImage& a, const engine::RenderedImage& b) {
        if (a.rgba.size() != b.rgba.size()) throw std::runtime_error("bench: images of different sizes");
        for (std::size_t p = 0; p + 3 < a.rgba.size(); p += 4) {
            int pixel = 0;
            for (std::size_t c = 0; c < 3; ++c) {
                pixel = std::max(pixel, std::abs(static_cast<int>(a.rgba[p + c]) - static_cast<int>(b.rgba[p + c])));
            }
            largestChannel = std::max(largestChannel, pixel);
            pixelsOver2Levels += pixel > 2 ? 1 : 0;
            ++pixels;
        }
    }

    double shareOver2Levels() const {
        return pixels > 0 ? static_cast<double>(pixelsOver2Levels) / static_cast<double>(pixels) : 0.0;
    }
};

}  // namespace bench
