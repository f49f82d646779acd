/// @brief Review sheets: a display's walls unfolded as a cross, eyes side by side, and a
/// red-cyan anaglyph, composed from rendered wall images.
#pragma once

#include <cstdint>
#include <map>
#include <vector>

#include "colon/rgba_image.h"
#include "engine/display/display.h"

namespace engine {

/// An 8-bit RGBA image, row 0 at the top: the one picture type of the project (the colon
/// analysis, below the engine, makes its overview and polyp crops in it too).
using RgbaImage = colon::RgbaImage;

/// An image of `width` x `height` filled with one colour.
RgbaImage filledImage(int width, int height, uint8_t r, uint8_t g, uint8_t b);

/// Box-filter reduction by an integer factor (the last partial blocks are averaged too).
RgbaImage downsampled(const RgbaImage& image, int factor);

/// Half-colour red-cyan anaglyph: red carries the left eye's luminance, green and blue the
/// right eye's own green and blue, which keeps colour while avoiding retinal rivalry in red.
/// Throws std::invalid_argument when the sizes differ.
RgbaImage anaglyphOf(const RgbaImage& left, const RgbaImage& right);

/// Where each wall lies in crossLayout's picture (pixels, row 0 at the top), and its size.
struct CrossCell {
    int x = 0, y = 0, width = 0, height = 0;
};
struct CrossGeometry {
    int width = 0, height = 0;
    std::map<WallName, CrossCell> cells;  ///< every wall of the cross, present on the display or not
};
CrossGeometry crossGeometry(const Display& display);

/// Dark pixels between the crosses of a review sheet (left eye, right eye, anaglyph).
inline constexpr int kSheetGapPixels = 16;

/// The walls laid out as an unfolded cube seen from inside: left, front, right, back in a row,
/// the ceiling above the front wall and the floor below it. Walls the display lacks (or that
/// `walls` does not hold) stay dark. Each wall is placed at its own pixel size.
RgbaImage crossLayout(const Display& display, const std::map<WallName, RgbaImage>& walls);

/// Images placed left to right with `gap` dark pixels between them, top-aligned.
RgbaImage sideBySide(const std::vector<RgbaImage>& images, int gap);

}  // namespace engine
