/// @brief The option groups several subcommands share, declared once: the volume (VOLUME,
/// --raw), the output (-o, --json, --force), the device, the display and the rays bent through
/// its map, and the path flown. Each subcommand binds them to its own fields.
#pragma once

#include <string>

namespace CLI {
class App;
class Option;
}  // namespace CLI

namespace app {

/// VOLUME (positional, also --volume; required) and --raw.
void addVolumeOptions(CLI::App& command, std::string& volumePath, std::string& rawSpec);

/// -o/--out (required when `isOutRequired`), --json FILE and --force, each with what it says for
/// this subcommand. Returns the -o option.
CLI::Option* addOutputOptions(CLI::App& command, std::string& out, const std::string& outHelp, bool isOutRequired,
                              std::string& jsonPath, const std::string& jsonHelp, bool& force, const std::string& forceHelp);

/// --device.
void addDeviceOption(CLI::App& command, std::string& device);

/// The display and the rays bent through its map. Null fields are not offered by the subcommand.
struct DisplayOptionFields {
    std::string* display = nullptr;
    std::string displayHelp = "ic5, ic6, cave6, cave4, forward or a display JSON file";
    std::string* map = nullptr;       // --map: override the display's map
    std::string* wallSize = nullptr;  // --wall-size WxH
    int* mapSize = nullptr;           // --map-size
    std::string mapSizeHelp = "Cube-map texels per face edge";
    std::string* warp = nullptr;      // --warp
    std::string warpHelp = "eye-centred (the display default), polyline, chord or exact";
    double* mmPerMetre = nullptr;     // --scale
};
void addDisplayOptions(CLI::App& command, const DisplayOptionFields& fields, const std::string& group = "");

/// The path flown: --path, --path-step, --smoothing, --retrograde and --frames.
struct PathOptionFields {
    std::string* pathFile = nullptr;
    std::string pathHelp;
    bool isPathRequired = false;
    double* stepMm = nullptr;
    double* smoothingMm = nullptr;
    bool* isRetrograde = nullptr;
    int* maxFrames = nullptr;
    std::string framesHelp = "Render at most this many frames of the path";
};
void addPathOptions(CLI::App& command, const PathOptionFields& fields, const std::string& group = "");

}  // namespace app
