#include "engine/display/display_json.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>

#include <nlohmann/json.hpp>

namespace engine {
namespace {

using nlohmann::json;

glm::dvec3 vec3Field(const json& document, const char* key, const glm::dvec3& fallback) {
    if (!document.contains(key)) return fallback;
    const json& value = document[key];
    if (!value.is_array() || value.size() != 3 || !value[0].is_number() || !value[1].is_number() ||
        !value[2].is_number()) {
        throw std::runtime_error(std::string("\"") + key + "\" must be three numbers");
    }
    return {value[0].get<double>(), value[1].get<double>(), value[2].get<double>()};
}

double numberField(const json& document, const char* key, double fallback) {
    if (!document.contains(key)) return fallback;
    if (!document[key].is_number()) throw std::runtime_error(std::string("\"") + key + "\" must be a number");
    return document[key].get<double>();
}

/// A pixel count: a whole number that fits an int. Converting a larger or fractional JSON number
/// to int would be undefined or would silently drop its fraction, so both are refused here;
/// validateDisplay then checks the range a wall may have.
int pixelField(const json& wall, const char* key, int fallback) {
    if (!wall.contains(key)) return fallback;
    const json& value = wall[key];
    const bool isWhole = value.is_number() && value.get<double>() == std::floor(value.get<double>()) &&
                         value.get<double>() >= std::numeric_limits<int>::min() &&
                         value.get<double>() <= std::numeric_limits<int>::max();
    if (!isWhole) {
        throw std::runtime_error("wall '" + wall["name"].get<std::string>() + "': \"" + key +
                                 "\" must be a whole number of pixels, not " + value.dump());
    }
    return static_cast<int>(value.get<double>());
}

Display displayFromJson(const json& document) {
    if (!document.is_object()) throw std::runtime_error("the top level must be an object");
    Display display;
    display.name = "custom";
    if (document.contains("name")) {
        if (!document["name"].is_string()) throw std::runtime_error("\"name\" must be a string");
        display.name = document["name"].get<std::string>();
    }
    display.boxSizeM = vec3Field(document, "box_size_m", display.boxSizeM);
    display.eyeSeparationM = numberField(document, "eye_separation_m", display.eyeSeparationM);
    display.headPositionM = vec3Field(document, "head_position_m", display.headPositionM);
    display.nearM = numberField(document, "near_m", display.nearM);
    if (document.contains("map")) {
        if (!document["map"].is_string()) throw std::runtime_error("\"map\" must be a string");
        display.map = conformal::mapKindFromName(document["map"].get<std::string>());
    }
    display.mapCentreM = vec3Field(document, "map_centre_m", display.mapCentreM);
    if (!document.contains("walls") || !document["walls"].is_array()) {
        throw std::runtime_error("\"walls\" must list the walls");
    }
    for (const json& wall : document["walls"]) {
        if (!wall.is_object() || !wall.contains("name") || !wall["name"].is_string()) {
            throw std::runtime_error("each wall needs a \"name\"");
        }
        DisplayWall entry;
        entry.name = wallNameFromText(wall["name"].get<std::string>());
        entry.width = pixelField(wall, "width", entry.width);
        entry.height = pixelField(wall, "height", entry.height);
        display.walls.push_back(entry);
    }
    return display;
}

}  // namespace

Display loadDisplay(const std::string& presetOrPath) {
    const auto presets = displayPresetNames();
    Display display;
    if (std::find(presets.begin(), presets.end(), presetOrPath) != presets.end()) {
        display = displayPreset(presetOrPath);
    } else {
        if (!std::filesystem::is_regular_file(presetOrPath)) {
            std::string names;
            for (const auto& preset : presets) names += (names.empty() ? "" : ", ") + preset;
            throw std::runtime_error("display '" + presetOrPath + "' is neither a preset (" + names +
                                     ") nor a JSON file");
        }
        std::ifstream in(presetOrPath);
        try {
            display = displayFromJson(json::parse(in));
        } catch (const std::exception& e) {
            throw std::runtime_error(presetOrPath + ": " + e.what());
        }
    }
    try {
        validateDisplay(display);
    } catch (const std::invalid_argument& e) {
        throw std::runtime_error(e.what());
    }
    return display;
}

Display displayFromJsonText(const std::string& text) {
    Display display;
    try {
        display = displayFromJson(json::parse(text));
        validateDisplay(display);
    } catch (const std::exception& e) {
        throw std::runtime_error(std::string("display JSON: ") + e.what());
    }
    return display;
}

std::string displayJson(const Display& display) {
    json document;
    document["name"] = display.name;
    document["box_size_m"] = {display.boxSizeM.x, display.boxSizeM.y, display.boxSizeM.z};
    document["map"] = conformal::mapKindName(display.map);
    document["map_centre_m"] = {display.mapCentreM.x, display.mapCentreM.y, display.mapCentreM.z};
    document["eye_separation_m"] = display.eyeSeparationM;
    document["head_position_m"] = {display.headPositionM.x, display.headPositionM.y, display.headPositionM.z};
    document["near_m"] = display.nearM;
    document["walls"] = json::array();
    for (const DisplayWall& wall : display.walls) {
        document["walls"].push_back({{"name", wallNameText(wall.name)}, {"width", wall.width}, {"height", wall.height}});
    }
    return document.dump(2);
}

}  // namespace engine
