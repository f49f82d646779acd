/// @brief How far apart two renders of the same view are, as the benchmarks report it beside
/// their times: per pixel the largest colour-channel difference (levels), summed up as the
/// largest one, the share of pixels more than N levels apart and the level a share of the
/// pixels stays within (the 99th percentile, say).
#pragma once

#include <algorithm>
#include <array>
#include <cstdlib>
#include <stdexcept>

#include "engine/render/render_settings.h"

namespace bench {

struct ImageDifference {
    int largestChannel = 0;
    std::size_t pixels = 0;
    std::array<std::size_t, 256> pixelsAtLevel{};  ///< pixels by their largest channel difference

    /// Adds the pixels of two RGBA renders of one size (alpha, always opaque, is not compared).
    void add(const engine::RenderedImage& a, const engine::RenderedImage& b) {
        if (a.rgba.size() != b.rgba.size()) throw std::runtime_error("bench: images of different sizes");
        for (std::size_t p = 0; p + 3 < a.rgba.size(); p += 4) {
            int pixel = 0;
            for (std::size_t c = 0; c < 3; ++c) {
                pixel = std::max(pixel, std::abs(static_cast<int>(a.rgba[p + c]) - static_cast<int>(b.rgba[p + c])));
            }
            largestChannel = std::max(largestChannel, pixel);
            ++pixelsAtLevel[static_cast<std::size_t>(pixel)];
            ++pixels;
        }
    }

    /// The share of pixels more than `levels` apart.
    double shareOver(int levels) const {
        std::size_t over = 0;
        for (std::size_t level = static_cast<std::size_t>(std::max(levels + 1, 0)); level < pixelsAtLevel.size(); ++level) {
            over += pixelsAtLevel[level];
        }
        return pixels > 0 ? static_cast<double>(over) / static_cast<double>(pixels) : 0.0;
    }
    double shareOver2Levels() const { return shareOver(2); }

    /// The least difference that `fraction` of the pixels stay within (0.99: the 99th percentile).
    int levelAtFraction(double fraction) const {
        std::size_t within = 0;
        for (std::size_t level = 0; level < pixelsAtLevel.size(); ++level) {
            within += pixelsAtLevel[level];
            if (static_cast<double>(within) >= fraction * static_cast<double>(pixels)) return static_cast<int>(level);
        }
        return largestChannel;
    }
};

}  // namespace bench
