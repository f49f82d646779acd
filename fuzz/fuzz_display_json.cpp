/// @brief libFuzzer target: display descriptions as `cvc render --display FILE` and the shared
/// render request read them (box, eyes, near plane, map, walls), checked by validateDisplay.
/// Beyond not crashing: the file reader and the text reader must agree, and a display that is
/// accepted must come back unchanged through the JSON that displayJson writes for it.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>

#include "engine/display/display_json.h"
#include "fuzz/fuzz_input_file.h"

namespace {

std::optional<engine::Display> fromText(const std::string& text) {
    try {
        return engine::displayFromJsonText(text);
    } catch (const std::runtime_error&) {
        return std::nullopt;  // refusing bad JSON or a display that cannot be rendered
    }
}

bool isSame(const engine::Display& a, const engine::Display& b) {
    if (a.name != b.name || a.boxSizeM != b.boxSizeM || a.eyeSeparationM != b.eyeSeparationM ||
        a.headPositionM != b.headPositionM || a.nearM != b.nearM || a.map != b.map || a.mapCentreM != b.mapCentreM ||
        a.walls.size() != b.walls.size()) {
        return false;
    }
    for (std::size_t w = 0; w < a.walls.size(); ++w) {
        if (a.walls[w].name != b.walls[w].name || a.walls[w].width != b.walls[w].width ||
            a.walls[w].height != b.walls[w].height) {
            return false;
        }
    }
    return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    const std::optional<engine::Display> display = fromText(text);

    std::optional<engine::Display> loaded;
    try {
        loaded = engine::loadDisplay(fuzz::writeInputFile(data, size, ".json"));
    } catch (const std::runtime_error&) {
        // The file reader refuses with a runtime_error, as the text reader does.
    }
    if (display.has_value() != loaded.has_value()) __builtin_trap();
    if (!display) return 0;
    if (!isSame(*display, *loaded)) __builtin_trap();

    const std::optional<engine::Display> again = fromText(engine::displayJson(*display));
    if (!again || !isSame(*display, *again)) __builtin_trap();
    for (const engine::DisplayWall& wall : display->walls) engine::wallRectangle(*display, wall.name);
    return 0;
}
