#include "app/render_options.h"

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

}  // namespace app
