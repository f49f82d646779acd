/// @brief Small parsers and checks shared by the subcommands' options.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "engine/display/display.h"

namespace app {

/// "1024x768" -> {1024, 768}; throws std::invalid_argument for anything else or sizes
/// outside 1..16384.
std::pair<int, int> parseImageSize(const std::string& text);

/// Three finite numbers from a command-line list; `option` names it in the error.
glm::dvec3 vec3From(const std::vector<double>& values, const std::string& option);

/// Throws before any work is done if `path` exists and `force` is false, or if its folder does
/// not exist or is not writable, so a long render never fails at its very end.
void requireWritableOutput(const std::string& path, bool force);

/// `--wall-size WxH`: the walls of `display` resized so that W pixels span the box's width, at the
/// same pixel density on every wall (the floor and the back keep their proportions; H is
/// checked like any size but follows from the box, as the display's own walls do).
void resizeWalls(engine::Display& display, const std::string& size);

/// Writes `text` to `path`, replacing it; throws std::runtime_error naming the file when the
/// write fails (a full disk, a file-size limit).
void writeTextFile(const std::string& path, const std::string& text);

}  // namespace app
