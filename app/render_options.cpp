#include "app/render_options.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include <CLI/CLI.hpp>

#include "app/option_parsing.h"
#include "engine/render/transfer_function.h"

namespace app {

engine::RenderSettings renderSettingsFrom(const RenderOptions& options, bool isDisplay) {
    const engine::RenderSettings defaults =
        engine::defaultRenderSettings(isDisplay ? engine::RenderUse::DisplayFrames : engine::RenderUse::Still);
    engine::RenderSettings settings = options.settings;
    settings.mode = options.mode == "composite" ? engine::RenderMode::Composite : engine::RenderMode::IsoSurface;
    settings.filter = options.filter == "tricubic" ? engine::VolumeFilter::Tricubic : engine::VolumeFilter::Trilinear;
    settings.gradient = options.gradient.empty() ? defaults.gradient : engine::gradientFilterFromName(options.gradient);
    settings.isSkipping = !options.isSkippingOff;
    settings.isUsingRayStartPass = !options.isStartPassOff;
    settings.isUsingGradientVolume =
        options.gradientVolume.empty() ? defaults.isUsingGradientVolume : options.gradientVolume == "on";
    // A value given is passed on as it is, so a bad one is refused by the ray caster's checks
    // instead of silently replaced.
    settings.lightHalfDistanceMm = options.lightHalfDistanceMm.value_or(defaults.lightHalfDistanceMm);
    settings.stepVoxels = options.stepVoxels.value_or(defaults.stepVoxels);
    if (settings.mode == engine::RenderMode::Composite) {
        engine::transferFunctionPreset(settings.transferFunction);  // a typo fails before any loading
    }
    return settings;
}

engine::PinholeCamera cameraFrom(const RenderOptions& options, const volumes::Volume& volume) {
    engine::PinholeCamera camera;
    const auto [width, height] = parseImageSize(options.size);
    camera.width = width;
    camera.height = height;
    camera.verticalFovDeg = options.fovDeg;
    const glm::dvec3 centre = (glm::dvec3(volume.dims[0], volume.dims[1], volume.dims[2]) - 1.0) * 0.5 * volume.spacingMm;
    camera.lookAtMm = options.lookAtMm.empty() ? centre : vec3From(options.lookAtMm, "--look-at");
    camera.up = options.up.empty() ? volumes::volumeDirectionFromPatient(volume, glm::dvec3(0.0, 0.0, 1.0))
                                   : vec3From(options.up, "--up");
    if (options.positionMm.empty()) {
        const double radius = 0.5 * glm::length(volume.extentMm());
        const double distance = radius / std::sin(glm::radians(std::min(options.fovDeg, 170.0)) * 0.5);
        const glm::dvec3 anterior = volumes::volumeDirectionFromPatient(volume, glm::dvec3(0.0, -1.0, 0.0));
        camera.positionMm = camera.lookAtMm + anterior * distance;
    } else {
        camera.positionMm = vec3From(options.positionMm, "--position");
    }
    return camera;
}

void checkDicomOutput(const std::string& folder, bool force) {
    namespace fs = std::filesystem;
    std::error_code error;
    if (!fs::exists(folder, error)) return;
    if (!fs::is_directory(folder, error)) throw std::invalid_argument("--dicom-out " + folder + ": is not a folder");
    for (const auto& entry : fs::directory_iterator(folder)) {
        if (!force && entry.path().extension() == ".dcm") {
            throw std::invalid_argument("--dicom-out " + folder + ": holds DICOM files (use --force to replace them)");
        }
    }
}

void refuseRenderOptionsNotApplying(const CLI::App& command, const RenderOptions& options) {
    if (options.display.empty()) {
        refuseGivenOptions(command,
                           {"--map", "--map-size", "--cube-map", "--warp", "--scale", "--before-after", "--path",
                            "--path-step", "--smoothing", "--retrograde", "--frames", "--distribute", "--polyp",
                            "--candidates", "--at-candidates", "--polyp-elevation", "--polyp-azimuth", "--resume"},
                           "is for display renders (--display); a pinhole view is one image from one camera");
    } else {
        refuseGivenOptions(command, {"--fov", "--size"},
                           "sets the pinhole camera; a display's walls have their own sizes and fields of view");
        refuseGivenOptions(command, {"--stats"}, "counts the fetches of a pinhole view; it is not for --display");
        if (options.pathFile.empty()) {
            refuseGivenOptions(command,
                               {"--path-step", "--smoothing", "--retrograde", "--frames", "--polyp", "--candidates",
                                "--at-candidates", "--polyp-elevation", "--polyp-azimuth"},
                               "needs --path: without it the display renders the one pose of --position");
        } else {
            refuseGivenOptions(command, {"--position", "--look-at", "--up"},
                               "sets a single pose; with --path the poses follow the centreline");
        }
        if (options.candidatesFile.empty()) refuseGivenOptions(command, {"--at-candidates"}, "needs --candidates");
        if (!options.isAtCandidates && !options.candidatesFile.empty()) {  // nearest frames of the antegrade flight
            if (options.polyp >= 0) throw std::invalid_argument("--candidates places them on a fly-through's frames; --polyp renders one pose");
            refuseGivenOptions(command, {"--retrograde"}, "reverses the frames cvc candidates placed the candidates on");
        }
        if (options.polyp >= 0) {
            refuseGivenOptions(command, {"--frames"}, "counts the frames of a fly-through; --polyp renders one pose");
            refuseGivenOptions(command, {"--at-candidates"}, "poses a frame per candidate; --polyp renders one pose");
        } else if (options.isAtCandidates) {
            refuseGivenOptions(command, {"--frames"}, "counts the frames of a fly-through; --at-candidates renders one per candidate");
        } else {
            refuseGivenOptions(command, {"--polyp-elevation", "--polyp-azimuth"}, "needs --polyp or --at-candidates");
        }
        if (!options.cubeMapFile.empty()) {
            refuseGivenOptions(command, {"--map-size"}, "is the bake's size; the file of --cube-map has its own");
        }
        refuseMapOptionsWithoutMap(command, options.display, options.map);
    }
    if (options.mode == "composite") {
        refuseGivenOptions(command, {"--iso", "--refine"}, "is for --mode iso; composite mode uses --tf");
    } else {
        refuseGivenOptions(command, {"--tf", "--early-termination"}, "is for --mode composite");
    }
    if (options.warp != "exact") refuseGivenOptions(command, {"--skip-bent-rays"}, "is for --warp exact");
    if (options.isSkippingOff) {
        refuseGivenOptions(command, {"--skip-cell", "--no-start-pass", "--look-in-every-tile", "--skip-bent-rays"},
                           "sets how empty space is skipped, which --no-skip turns off");
    }
    if (options.isStartPassOff) {
        refuseGivenOptions(command, {"--look-in-every-tile"}, "is for the tile pass, which --no-start-pass turns off");
    }
    if (options.filter == "tricubic" && !options.gradient.empty() && options.gradient != "bspline") {
        throw std::invalid_argument("--gradient " + options.gradient +
                                    ": the tricubic filter always shades with B-spline normals");
    }
}

}  // namespace app
