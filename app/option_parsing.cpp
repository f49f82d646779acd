#include "app/option_parsing.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include <unistd.h>

#include <CLI/CLI.hpp>

#include "conformal/cube_map.h"
#include "engine/display/display_json.h"
#include "engine/render/pinhole_camera.h"

namespace app {

void refuseGivenOptions(const CLI::App& command, std::initializer_list<const char*> options, const std::string& why) {
    for (const char* option : options) {
        if (command.count(option) > 0) throw std::invalid_argument(std::string(option) + " " + why);
    }
}

void refuseMapOptionsWithoutMap(const CLI::App& command, const std::string& display, const std::string& mapOverride) {
    const conformal::MapKind map =
        mapOverride.empty() ? engine::loadDisplay(display).map : conformal::mapKindFromName(mapOverride);
    if (map != conformal::MapKind::None) return;
    for (const char* option : {"--map-size", "--cube-map", "--warp"}) {
        const CLI::Option* given = command.get_option_no_throw(option);  // not every command has all three
        if (given != nullptr && given->count() > 0) {
            throw std::invalid_argument(std::string(option) + " bends the rays through a map, and " + display +
                                        " is rendered without one here");
        }
    }
}

std::pair<int, int> parseImageSize(const std::string& text, const std::string& option) {
    const auto x = text.find('x');
    std::size_t usedWidth = 0, usedHeight = 0;
    int width = 0, height = 0;
    try {
        if (x == std::string::npos) throw std::invalid_argument("no x");
        width = std::stoi(text.substr(0, x), &usedWidth);
        height = std::stoi(text.substr(x + 1), &usedHeight);
    } catch (const std::exception&) {
        throw std::invalid_argument(option + " '" + text + "' is not WIDTHxHEIGHT");
    }
    if (usedWidth != x || usedHeight != text.size() - x - 1 || width < 1 || height < 1 ||
        width > engine::kMaxImageSide || height > engine::kMaxImageSide) {
        throw std::invalid_argument(option + " '" + text + "' must be WIDTHxHEIGHT with sides 1.." +
                                    std::to_string(engine::kMaxImageSide));
    }
    return {width, height};
}

glm::dvec3 vec3From(const std::vector<double>& values, const std::string& option) {
    if (values.size() != 3 || !std::isfinite(values[0]) || !std::isfinite(values[1]) || !std::isfinite(values[2])) {
        throw std::invalid_argument(option + " needs three finite numbers x,y,z");
    }
    return {values[0], values[1], values[2]};
}

void requireWritableOutput(const std::string& path, bool force) {
    namespace fs = std::filesystem;
    if (!force && fs::exists(path)) {
        throw std::runtime_error(path + ": exists already (pass --force to replace it)");
    }
    const fs::path parent = fs::absolute(fs::path(path)).parent_path();
    if (!fs::is_directory(parent)) {
        throw std::runtime_error(path + ": output folder " + parent.string() + " does not exist");
    }
    if (access(parent.c_str(), W_OK) != 0) {
        throw std::runtime_error(path + ": output folder " + parent.string() + " is not writable");
    }
}

void resizeWalls(engine::Display& display, const std::string& size) {
    engine::resizeWallsToWidth(display, parseImageSize(size, "--wall-size").first);
}

}  // namespace app
