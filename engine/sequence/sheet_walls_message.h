/// @brief The message a rank sends rank 0 when it has written a frame under the frames
/// distribution: the frame's index and its walls reduced for the review sheet, so that rank 0
/// writes the sheet without reading the full-size walls back from the files.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <vector>

#include "engine/review/review_sheet.h"

namespace engine {

struct SheetWalls {
    int frameIndex = 0;
    std::vector<RgbaImage> walls;  // eye after eye, walls in the display's order
};

/// Raised when a message does not hold what packSheetWalls writes.
class SheetWallsMessageError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// Little-endian: the index, the image count, then per image its width, height and RGBA rows.
std::vector<unsigned char> packSheetWalls(const SheetWalls& sheetWalls);
/// The inverse of packSheetWalls; throws SheetWallsMessageError on a short, long or inconsistent message.
SheetWalls unpackSheetWalls(const std::vector<unsigned char>& message);

}  // namespace engine
