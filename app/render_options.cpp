#include "app/render_options.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>

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

}  // namespace app
