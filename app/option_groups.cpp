#include "app/option_groups.h"

#include <CLI/CLI.hpp>

#include "engine/display/display.h"

namespace app {
namespace {

/// Puts `option` under `group` in the help; an empty group keeps CLI11's default ("Options"),
/// where CLI11's own empty group would hide the option.
CLI::Option* inGroup(CLI::Option* option, const std::string& group) {
    return group.empty() ? option : option->group(group);
}

}  // namespace

void addVolumeOptions(CLI::App& command, std::string& volumePath, std::string& rawSpec) {
    command.add_option("volume,--volume", volumePath,
                       "Volume: DICOM folder, .nrrd/.nhdr, .nii/.nii.gz, .mha/.mhd, .vdb, or raw with --raw")
        ->required();
    command.add_option("--raw", rawSpec, "Describe a headerless raw file, e.g. 512x512x451:int16:0.7x0.7x1.25");
}

CLI::Option* addOutputOptions(CLI::App& command, std::string& out, const std::string& outHelp, bool isOutRequired,
                              std::string& jsonPath, const std::string& jsonHelp, bool& force, const std::string& forceHelp) {
    CLI::Option* option = command.add_option("-o,--out", out, outHelp);
    if (isOutRequired) option->required();
    command.add_option("--json", jsonPath, jsonHelp);
    command.add_flag("--force", force, forceHelp);
    return option;
}

void addDeviceOption(CLI::App& command, std::string& device) {
    command.add_option("--device", device,
                       "Vulkan device: index, part of its name, 'cpu' or 'gpu' (default: $CVC_DEVICE, else the best)");
}

void addDisplayOptions(CLI::App& command, const DisplayOptionFields& fields, const std::string& group) {
    if (fields.display) inGroup(command.add_option("--display", *fields.display, fields.displayHelp)->capture_default_str(), group);
    if (fields.map) {
        inGroup(command.add_option("--map", *fields.map, "Override the display's map: conformal, linear, none")
            ->check(CLI::IsMember({"conformal", "linear", "none"})), group);
    }
    if (fields.wallSize) {
        inGroup(command.add_option("--wall-size", *fields.wallSize,
                           "Walls resized to WxH across the box's width at one pixel density (default: the display's own)")
            , group);
    }
    if (fields.mapSize) inGroup(command.add_option("--map-size", *fields.mapSize, fields.mapSizeHelp)->capture_default_str(), group);
    if (fields.warp) {
        inGroup(command.add_option("--warp", *fields.warp, fields.warpHelp)
            ->check(CLI::IsMember(engine::bendingWarpModeNames()))->capture_default_str(), group);
    }
    if (fields.mmPerMetre) {
        inGroup(command.add_option("--scale", *fields.mmPerMetre, "Volume millimetres per CAVE metre")->capture_default_str(), group);
    }
}

void addPathOptions(CLI::App& command, const PathOptionFields& fields, const std::string& group) {
    CLI::Option* path = inGroup(command.add_option("--path", *fields.pathFile, fields.pathHelp), group);
    if (fields.isPathRequired) path->required();
    inGroup(command.add_option("--path-step", *fields.stepMm, "Arc length between frames in mm")->capture_default_str(), group);
    inGroup(command.add_option("--smoothing", *fields.smoothingMm, "Half-width in mm of the view-direction smoothing")
        ->capture_default_str(), group);
    inGroup(command.add_flag("--retrograde", *fields.isRetrograde, "Fly caecum -> rectum (default: antegrade, rectum -> caecum)")
        , group);
    inGroup(command.add_option("--frames", *fields.maxFrames, fields.framesHelp), group);
}

}  // namespace app
