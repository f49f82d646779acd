#include "bench/display_frame_scene.h"

#include <stdexcept>

#include "engine/display/display_json.h"
#include "volumes/load_volume.h"

namespace bench {

void addDisplayFrameOptions(CLI::App* command, DisplayFrameRequest& request) {
    command->add_option("volume", request.volumePath, "Volume file")->required();
    command->add_option("--display", request.display, "Display preset or JSON")->capture_default_str();
    command->add_option("--path", request.pathFile, "Path with ground truth (e.g. a phantom's JSON)")->required();
    command->add_option("--polyp", request.polyp, "The polyp whose viewing pose is rendered")->capture_default_str();
    command->add_option("--polyp-elevation", request.polypElevationDeg, "Its elevation in degrees")->capture_default_str();
    command->add_option("--map-size", request.mapSize, "Cube-map texels per face edge")->capture_default_str();
    command->add_option("--runs", request.runs, "Repetitions of each mode (medians are reported)")->capture_default_str();
    command->add_option("--device", request.device, "Vulkan device");
}

DisplayFrameScene loadDisplayFrameScene(const DisplayFrameRequest& request) {
    if (request.runs < 1 || request.runs > 1000) throw std::invalid_argument("--runs must be 1 to 1000");
    DisplayFrameScene scene;
    scene.volume = volumes::loadVolume(request.volumePath);
    scene.bricks = volumes::buildBrickMinMax(scene.volume);
    scene.display = engine::loadDisplay(request.display);
    engine::PoseRequest poseRequest;
    poseRequest.pathFile = request.pathFile;
    poseRequest.polyp = request.polyp;
    poseRequest.polypElevationDeg = request.polypElevationDeg;
    scene.pose = engine::posesFor(poseRequest).at(0);
    return scene;
}

engine::RenderSettings displayFrameSettings() {
    engine::RenderSettings settings;
    settings.stepVoxels = 1.0;
    settings.lightHalfDistanceMm = 25.0;
    settings.gradient = engine::GradientFilter::Central;
    settings.isWritingHits = false;  // as display frames without --hits
    return settings;
}

}  // namespace bench
