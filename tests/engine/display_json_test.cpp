// Display JSON: the refusals found by fuzz/fuzz_display_json (corpus inputs named in each test).
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "engine/display/display_json.h"

namespace {

std::string displayWithFrontWall(const std::string& width) {
    return R"({"map": "none", "walls": [{"name": "front", "width": )" + width + R"(, "height": 1024}]})";
}

/// The message of the runtime_error displayFromJsonText throws for `text`; empty if it accepts it.
std::string refusal(const std::string& text) {
    try {
        engine::displayFromJsonText(text);
    } catch (const std::runtime_error& e) {
        return e.what();
    }
    return {};
}

TEST(DisplayJson, PixelCountsBeyondIntAreRefusedByName) {
    // fuzz/corpus/display_json/wall_width_1e24.json: converting 1e24 to int is undefined
    // behaviour; the reader must refuse the number itself, naming the wall and the field.
    for (const char* width : {"1E024", "-1e300", "4294967296", "2147483648"}) {
        const std::string message = refusal(displayWithFrontWall(width));
        EXPECT_NE(message.find("wall 'front': \"width\" must be a whole number of pixels"), std::string::npos)
            << width << ": " << message;
    }
}

TEST(DisplayJson, FractionalAndNonNumericPixelCountsAreRefused) {
    // 1400.5 used to become 1400 without a word.
    for (const char* width : {"1400.5", "\"1400\"", "null", "[1400]"}) {
        const std::string message = refusal(displayWithFrontWall(width));
        EXPECT_NE(message.find("must be a whole number of pixels"), std::string::npos) << width << ": " << message;
    }
    // A whole number written with a fraction part is still a whole number.
    EXPECT_EQ(engine::displayFromJsonText(displayWithFrontWall("1400.0")).walls.at(0).width, 1400);
    // In range for int but not for a wall: validateDisplay's message.
    EXPECT_NE(refusal(displayWithFrontWall("0")).find("must be 1..16384 pixels"), std::string::npos);
}

TEST(DisplayJson, NameMustBeAString) {
    const std::string message = refusal(R"({"name": 5, "map": "none", "walls": [{"name": "front"}]})");
    EXPECT_NE(message.find("\"name\" must be a string"), std::string::npos) << message;
}

TEST(DisplayJson, WrittenDisplaysReadBackUnchanged) {
    for (const std::string& preset : engine::displayPresetNames()) {
        if (preset == "cave4") continue;  // refused with its map (a missing wall too many)
        const engine::Display display = engine::displayPreset(preset);
        const engine::Display again = engine::displayFromJsonText(engine::displayJson(display));
        EXPECT_EQ(again.name, display.name);
        EXPECT_EQ(again.boxSizeM, display.boxSizeM);
        EXPECT_EQ(again.map, display.map);
        ASSERT_EQ(again.walls.size(), display.walls.size());
        for (std::size_t w = 0; w < display.walls.size(); ++w) {
            EXPECT_EQ(again.walls[w].width, display.walls[w].width) << preset;
            EXPECT_EQ(again.walls[w].height, display.walls[w].height) << preset;
        }
    }
}

}  // namespace
