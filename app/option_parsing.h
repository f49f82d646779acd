/// @brief Small parsers and checks shared by the subcommands' options.
#pragma once

#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "engine/display/display.h"
#include "engine/output/text_file.h"

namespace CLI {
class App;
}

namespace app {

/// Refuses the first of `options` given on `command`'s line with "OPTION WHY" (a
/// std::invalid_argument): an option that does not apply to what was asked is an error the user
/// sees, never a value silently ignored.
void refuseGivenOptions(const CLI::App& command, std::initializer_list<const char*> options, const std::string& why);

/// `--map-size`, `--cube-map` and `--warp` shape the rays bent through a display's map: they are
/// refused when the display (`display`, a preset or JSON file, after the `--map` override
/// `mapOverride` unless empty) has no map. Throws what loadDisplay throws for a bad display.
void refuseMapOptionsWithoutMap(const CLI::App& command, const std::string& display, const std::string& mapOverride);

/// "1024x768" -> {1024, 768}; throws std::invalid_argument naming `option` for anything else or
/// sizes outside 1..16384.
std::pair<int, int> parseImageSize(const std::string& text, const std::string& option = "--size");

/// Three finite numbers from a command-line list; `option` names it in the error.
glm::dvec3 vec3From(const std::vector<double>& values, const std::string& option);

/// Throws before any work is done if `path` exists and `force` is false, or if its folder does
/// not exist or is not writable, so a long render never fails at its very end.
void requireWritableOutput(const std::string& path, bool force);

/// `--wall-size WxH`: the walls of `display` resized so that W pixels span the box's width, at the
/// same pixel density on every wall (the floor and the back keep their proportions; H is
/// checked like any size but follows from the box, as the display's own walls do).
void resizeWalls(engine::Display& display, const std::string& size);

/// Every command writes its text outputs (--json summaries, tables) through the engine's one writer.
using engine::writeTextFile;

}  // namespace app
