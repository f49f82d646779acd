// The message a rank sends rank 0 with a written frame's walls reduced for its sheet: what is
// packed comes back pixel for pixel, and a short, long or inconsistent message is refused.
#include <gtest/gtest.h>

#include "engine/sequence/sheet_walls_message.h"

namespace {

engine::SheetWalls someWalls() {
    engine::SheetWalls sheetWalls;
    sheetWalls.frameIndex = 417;
    for (int i = 0; i < 10; ++i) {
        engine::RgbaImage wall{3 + i, 2 + (i % 3), {}};
        for (int p = 0; p < 4 * wall.width * wall.height; ++p) wall.rgba.push_back(static_cast<uint8_t>(p * 7 + i));
        sheetWalls.walls.push_back(wall);
    }
    sheetWalls.walls.push_back({0, 0, {}});  // an empty wall (another rank's, under walls) survives too
    return sheetWalls;
}

TEST(SheetWallsMessage, WhatIsPackedComesBackPixelForPixel) {
    const engine::SheetWalls sent = someWalls();
    const engine::SheetWalls received = engine::unpackSheetWalls(engine::packSheetWalls(sent));
    EXPECT_EQ(received.frameIndex, 417);
    ASSERT_EQ(received.walls.size(), sent.walls.size());
    for (std::size_t i = 0; i < sent.walls.size(); ++i) {
        EXPECT_EQ(received.walls[i].width, sent.walls[i].width) << i;
        EXPECT_EQ(received.walls[i].height, sent.walls[i].height) << i;
        EXPECT_EQ(received.walls[i].rgba, sent.walls[i].rgba) << i;
    }
}

TEST(SheetWallsMessage, EveryShortenedOrLengthenedMessageIsRefused) {
    const std::vector<unsigned char> message = engine::packSheetWalls(someWalls());
    for (std::size_t size = 0; size < message.size(); ++size) {
        const std::vector<unsigned char> cut(message.begin(), message.begin() + static_cast<std::ptrdiff_t>(size));
        EXPECT_THROW((void)engine::unpackSheetWalls(cut), engine::SheetWallsMessageError) << size;
    }
    std::vector<unsigned char> longer = message;
    longer.push_back(0);
    EXPECT_THROW((void)engine::unpackSheetWalls(longer), engine::SheetWallsMessageError);
}

TEST(SheetWallsMessage, AbsurdCountsAndSidesAndInconsistentImagesAreRefused) {
    // 13 images (more than a box's walls for two eyes), then a 1e6-pixel side: refused before
    // anything is allocated for them.
    const std::vector<unsigned char> tooMany = {1, 0, 0, 0, 13, 0, 0, 0};
    EXPECT_THROW((void)engine::unpackSheetWalls(tooMany), engine::SheetWallsMessageError);
    const std::vector<unsigned char> tooWide = {1, 0, 0, 0, 1, 0, 0, 0, 0x40, 0x42, 0x0f, 0, 1, 0, 0, 0};
    EXPECT_THROW((void)engine::unpackSheetWalls(tooWide), engine::SheetWallsMessageError);
    const std::vector<unsigned char> negativeIndex = {0xff, 0xff, 0xff, 0xff, 0, 0, 0, 0};
    EXPECT_THROW((void)engine::unpackSheetWalls(negativeIndex), engine::SheetWallsMessageError);
    engine::SheetWalls inconsistent;
    inconsistent.walls.push_back({4, 4, std::vector<uint8_t>(10)});
    EXPECT_THROW((void)engine::packSheetWalls(inconsistent), engine::SheetWallsMessageError);
}

}  // namespace
