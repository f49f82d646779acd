/// @brief `cvc render`: load a CT volume and render it from a pinhole camera to a PNG (and,
/// on request, the first-hit positions as a float image).
#include <chrono>
#include <cmath>
#include <iostream>
#include <memory>
#include <stdexcept>

#include <CLI/CLI.hpp>

#include "app/commands.h"
#include "app/option_parsing.h"
#include "engine/gpu_context.h"
#include "engine/hit_image_writer.h"
#include "engine/pinhole_camera.h"
#include "engine/png_writer.h"
#include "engine/raycaster.h"
#include "engine/transfer_function.h"
#include "engine/view_rays.h"
#include "engine/volume_texture.h"
#include "volumes/load_volume.h"

namespace app {
namespace {

struct RenderOptions {
    std::string volumePath;
    std::string rawSpec;
    std::string outPath = "render.png";
    std::string hitsPath;
    std::vector<double> positionMm;
    std::vector<double> lookAtMm;
    std::vector<double> up;
    double fovDeg = 40.0;
    std::string size = "1024x1024";
    std::string mode = "iso";
    std::string filter = "trilinear";
    engine::RenderSettings settings;
    bool isSkippingOff = false;
    std::string device;
    bool force = false;
};

/// With no position given, the camera looks at the volume's centre from the patient's front
/// (anterior, −y in LPS) with the head up (+z), whatever order the file stores the axes in,
/// far enough back for the whole box to fit the field of view.
engine::PinholeCamera cameraFrom(const RenderOptions& options, const volumes::Volume& volume) {
    engine::PinholeCamera camera;
    const auto [width, height] = parseImageSize(options.size);
    camera.width = width;
    camera.height = height;
    camera.verticalFovDeg = options.fovDeg;
    const glm::dvec3 centre = (glm::dvec3(volume.dims[0], volume.dims[1], volume.dims[2]) - 1.0) * 0.5 * volume.spacingMm;
    camera.lookAtMm = options.lookAtMm.empty() ? centre : vec3From(options.lookAtMm, "--look-at");
    // Patient-frame vectors become volume-frame vectors through the inverse (transpose) of
    // the orthonormal direction matrix.
    const glm::dmat3 volumeFromPatient = glm::transpose(volume.directionLps);
    camera.up = options.up.empty() ? volumeFromPatient * glm::dvec3(0.0, 0.0, 1.0) : vec3From(options.up, "--up");
    if (options.positionMm.empty()) {
        const double radius = 0.5 * glm::length(volume.extentMm());
        const double distance = radius / std::sin(glm::radians(std::min(options.fovDeg, 170.0)) * 0.5);
        const glm::dvec3 anterior = volumeFromPatient * glm::dvec3(0.0, -1.0, 0.0);
        camera.positionMm = camera.lookAtMm + anterior * distance;
    } else {
        camera.positionMm = vec3From(options.positionMm, "--position");
    }
    return camera;
}

void runRender(RenderOptions options) {
    requireWritableOutput(options.outPath, options.force);
    if (!options.hitsPath.empty()) requireWritableOutput(options.hitsPath, options.force);
    options.settings.mode = options.mode == "composite" ? engine::RenderMode::Composite : engine::RenderMode::IsoSurface;
    options.settings.filter = options.filter == "tricubic" ? engine::VolumeFilter::Tricubic : engine::VolumeFilter::Trilinear;
    options.settings.isSkipping = !options.isSkippingOff;
    options.settings.isWritingHits = !options.hitsPath.empty();
    if (options.settings.mode == engine::RenderMode::Composite) {
        engine::transferFunctionPreset(options.settings.transferFunction);  // a typo fails before loading
    }

    const auto start = std::chrono::steady_clock::now();
    volumes::LoadOptions load;
    if (!options.rawSpec.empty()) load.raw = volumes::parseRawSpec(options.rawSpec);
    const volumes::LoadedVolume loaded = volumes::loadVolumeWithBricks(options.volumePath, load);
    const engine::PinholeCamera camera = cameraFrom(options, loaded.volume);

    engine::GpuContext context(engine::GpuContextOptions{false, options.device});
    engine::VolumeTexture texture(context, loaded.volume);
    engine::Raycaster raycaster(context, texture, loaded.bricks);
    const engine::RenderedImage image = raycaster.render(engine::viewRaysFrom(camera), options.settings);
    engine::writePng(options.outPath, image.width, image.height, image.rgba, options.force);
    if (!options.hitsPath.empty()) {
        engine::writeHitImageNrrd(options.hitsPath, image.width, image.height, image.hitMm, options.force);
    }

    const double totalS = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::cout << "rendered " << image.width << "x" << image.height << " on " << context.deviceName() << ": ";
    if (image.deviceMs >= 0.0) std::cout << "ray casting " << image.deviceMs << " ms, ";
    std::cout << "total " << totalS << " s\nwrote " << options.outPath << '\n';
    if (!options.hitsPath.empty()) std::cout << "wrote " << options.hitsPath << '\n';
}

}  // namespace

void addRenderCommand(CLI::App& program) {
    auto options = std::make_shared<RenderOptions>();
    engine::RenderSettings& s = options->settings;
    CLI::App* command = program.add_subcommand("render", "Render a CT volume from a pinhole camera to a PNG");
    command->add_option("volume,--volume", options->volumePath,
                        "Volume: DICOM folder, .nrrd/.nhdr, .nii/.nii.gz, .mha/.mhd, .vdb, or raw with --raw")
        ->required();
    command->add_option("--raw", options->rawSpec, "Describe a headerless raw file, e.g. 512x512x451:int16:0.7x0.7x1.25");
    command->add_option("-o,--out", options->outPath, "Output PNG file")->capture_default_str();
    command->add_option("--hits", options->hitsPath, "Also write first-hit positions (volume mm) to this .nrrd file");
    command->add_option("--position", options->positionMm, "Camera position x,y,z in volume mm")
        ->expected(3)->delimiter(',');
    command->add_option("--look-at", options->lookAtMm, "Point looked at, x,y,z in volume mm (default: centre)")
        ->expected(3)->delimiter(',');
    command->add_option("--up", options->up, "Up vector x,y,z in volume axes (default: the patient's head)")
        ->expected(3)->delimiter(',');
    command->add_option("--fov", options->fovDeg, "Vertical field of view in degrees")->capture_default_str();
    command->add_option("--size", options->size, "Image size WIDTHxHEIGHT in pixels")->capture_default_str();
    command->add_option("--mode", options->mode, "iso (first crossing of --iso) or composite (--tf)")
        ->check(CLI::IsMember({"iso", "composite"}))->capture_default_str();
    command->add_option("--iso", s.isoHu, "Iso value in HU")->capture_default_str();
    command->add_option("--tf", s.transferFunction, "Transfer function preset: colon-wall, soft-tissue, bone")
        ->capture_default_str();
    command->add_option("--step", s.stepVoxels, "March step in voxels")->capture_default_str();
    command->add_option("--refine", s.refinementSteps, "Bisection steps refining each iso hit (0: none)")
        ->capture_default_str();
    command->add_option("--filter", options->filter, "trilinear (fast) or tricubic (B-spline, for stills)")
        ->check(CLI::IsMember({"trilinear", "tricubic"}))->capture_default_str();
    command->add_flag("--no-skip", options->isSkippingOff, "Turn off empty-space skipping");
    command->add_flag("--adaptive", s.isAdaptive, "Lengthen steps where a pixel covers more than a voxel");
    command->add_option("--jitter", s.jitterSeed, "Jitter ray starts with this seed (same seed, same image)")
        ->each([&s](const std::string&) { s.isJittered = true; });
    command->add_option("--light-distance", s.lightHalfDistanceMm,
                        "Distance in mm at which the headlight is half as bright (0: no falloff)")
        ->capture_default_str();
    command->add_option("--device", options->device,
                        "Vulkan device: index, part of its name, 'cpu' or 'gpu' (default: $CVC_DEVICE, else the best)");
    command->add_flag("--force", options->force, "Replace existing output files");
    command->callback([options] { runRender(*options); });
}

}  // namespace app
