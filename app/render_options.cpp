#include "app/render_options.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "app/option_parsing.h"
#include "engine/render/transfer_function.h"

namespace app {

engine::RenderSettings renderSettingsFrom(const RenderOptions& options, bool isDisplay) {
    engine::RenderSettings settings = options.settings;
    settings.mode = options.mode == "composite" ? engine::RenderMode::Composite : engine::RenderMode::IsoSurface;
    settings.filter = options.filter == "tricubic" ? engine::VolumeFilter::Tricubic : engine::VolumeFilter::Trilinear;
    // Stills get smooth normals; display frames, which come by the dozen from inside the colon
    // where the bands hardly show, keep the 4x cheaper trilinear ones (docs/benchmarks/normals.md).
    const std::string gradient = !options.gradient.empty() ? options.gradient : isDisplay ? "central" : "bspline";
    settings.gradient = gradient == "central" ? engine::GradientFilter::Central : engine::GradientFilter::BSpline;
    settings.isSkipping = !options.isSkippingOff;
    settings.isUsingRayStartPass = !options.isStartPassOff;
    // The gradient volume pays for itself over many frames; a single still would spend longer
    // computing it (1.3-1.7 s for the 512x512x451 yardstick here) than it saves (docs/benchmarks/march.md).
    settings.isUsingGradientVolume = options.gradientVolume.empty() ? isDisplay : options.gradientVolume == "on";
    // Each default is chosen here, once; a value given is passed on as it is, so a bad one is
    // refused by the ray caster's checks instead of silently replaced.
    settings.lightHalfDistanceMm = options.lightHalfDistanceMm.value_or(isDisplay ? 25.0 : 0.0);
    // Display frames come by the dozen and their hits are refined by bisection: a voxel-long
    // step halves their time; a still keeps the finer default.
    settings.stepVoxels = options.stepVoxels.value_or(isDisplay ? 1.0 : 0.5);
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
