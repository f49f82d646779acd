/// @brief Display descriptions as JSON files, so a site describes its own CAVE.
#pragma once

#include <string>

#include "engine/display/display_description.h"

namespace engine {

/// A preset name ("ic5", "ic6", "cave6", "cave4", "forward") or the path of a JSON file such as
///   {"name": "lab", "box_size_m": [3, 2.4, 3], "map": "conformal", "map_centre_m": [0, 0, 0],
///    "eye_separation_m": 0.065, "head_position_m": [0, 0, 0], "near_m": 0.05,
///    "walls": [{"name": "front", "width": 1400, "height": 1050}, ...]}
/// Omitted fields keep the defaults of Display. Throws std::runtime_error naming the file and
/// field for unreadable files, wrong types and unknown names; the result is validated.
Display loadDisplay(const std::string& presetOrPath);

/// The display that JSON text in loadDisplay's format describes (what displayJson wrote), validated.
Display displayFromJsonText(const std::string& text);

/// The JSON text of `display` in the format loadDisplay reads.
std::string displayJson(const Display& display);

}  // namespace engine
