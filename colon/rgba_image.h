/// @brief An 8-bit RGBA picture, row 0 at the top: the colon analysis's overview and polyp crops,
/// and the engine's wall images and review sheets (engine::RgbaImage is this type).
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
