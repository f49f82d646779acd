/// @brief An 8-bit RGBA picture made by the colon analysis (overview, polyp crops), row 0 at the
/// top; the app writes it as PNG.
#pragma once

#include <cstdint>
#include <vector>

namespace colon {

struct RgbaImage {
    int width = 0;
    int height = 0;
    std::vector<uint8_t> rgba;
};

}  // namespace colon
