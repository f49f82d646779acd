/// @brief What the display-frame benchmarks (`cvc_bench warp`, `cvc_bench stereo`) set up alike:
/// the volume with its brick min/max, the display, the camera pose of the demo's scene, and the
/// settings `cvc render --display` gives display frames.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

#include "engine/display/display_description.h"
#include "engine/render/render_settings.h"
#include "engine/sequence/camera_path.h"
#include "volumes/brick_minmax.h"
#include "volumes/volume.h"

namespace bench {

/// What the display-frame benchmarks take on the command line alike.
struct DisplayFrameRequest {
    std::string volumePath;
    std::string display = "ic5";
    std::string pathFile;  ///< a ground truth with polyps: the pose viewing `polyp`
    int polyp = 0;
    double polypElevationDeg = 50.0;
    int mapSize = 1024;
    int runs = 5;
    std::string device;
};

/// The request's options (VOLUME, --display, --path, --polyp, --polyp-elevation, --map-size,
/// --runs, --device) on `command`.
void addDisplayFrameOptions(CLI::App* command, DisplayFrameRequest& request);

struct DisplayFrameScene {
    volumes::Volume volume;
    volumes::BrickMinMax bricks;
    engine::Display display;
    engine::CameraPose pose;  ///< the first pose the path file gives (with a polyp: the pose viewing it)
};

/// Loads the volume and the display (a preset name or a display JSON file) and takes the pose
/// as `cvc render` would from the request's path file, polyp and elevation (engine::posesFor).
/// Throws std::invalid_argument for runs outside 1 to 1000.
DisplayFrameScene loadDisplayFrameScene(const DisplayFrameRequest& request);

/// `cvc render --display`'s defaults for display frames (app/render_command.cpp), without hits.
engine::RenderSettings displayFrameSettings();

}  // namespace bench
