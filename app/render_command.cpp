/// @brief `cvc render`: load a CT volume and render it from a pinhole camera to a PNG.
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <stdexcept>

#include <CLI/CLI.hpp>

#include "app/commands.h"
#include "app/option_parsing.h"
#include "engine/gpu_context.h"
#include "engine/iso_surface_renderer.h"
#include "engine/pinhole_camera.h"
#include "engine/png_writer.h"
#include "engine/volume_texture.h"
#include "volumes/nrrd_io.h"

namespace app {
namespace {

struct RenderOptions {
    std::string volumePath;
    std::string outPath = "render.png";
    std::vector<double> positionMm;
    std::vector<double> lookAtMm;
    std::vector<double> up;
    double fovDeg = 40.0;
    std::string size = "1024x1024";
    double isoHu = -500.0;
    double stepVoxels = 0.5;
    int bisectionSteps = 6;
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

void runRender(const RenderOptions& options) {
    requireWritableOutput(options.outPath, options.force);
    const auto start = std::chrono::steady_clock::now();
    const volumes::Volume volume = volumes::readNrrd(options.volumePath);
    const engine::PinholeCamera camera = cameraFrom(options, volume);

    engine::GpuContext context(engine::GpuContextOptions{false, options.device});
    engine::VolumeTexture texture(context, volume);
    engine::IsoSurfaceRenderer renderer(context, texture);
    const engine::RenderedImage image =
        renderer.render(camera, engine::IsoSurfaceSettings{options.isoHu, options.stepVoxels, options.bisectionSteps});
    engine::writePng(options.outPath, image.width, image.height, image.rgba, options.force);

    const double totalS = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::cout << "rendered " << image.width << "x" << image.height << " on " << context.deviceName() << ": ";
    if (image.deviceMs >= 0.0) std::cout << "ray casting " << image.deviceMs << " ms, ";
    std::cout << "total " << totalS << " s\nwrote " << options.outPath << '\n';
}

}  // namespace

void addRenderCommand(CLI::App& program) {
    auto options = std::make_shared<RenderOptions>();
    CLI::App* command = program.add_subcommand("render", "Render a CT volume to a PNG (iso-surface, headlight)");
    command->add_option("volume,--volume", options->volumePath, "Volume file (NRRD)")->required();
    command->add_option("-o,--out", options->outPath, "Output PNG file")->capture_default_str();
    command->add_option("--position", options->positionMm, "Camera position x,y,z in volume mm")
        ->expected(3)->delimiter(',');
    command->add_option("--look-at", options->lookAtMm, "Point looked at, x,y,z in volume mm (default: centre)")
        ->expected(3)->delimiter(',');
    command->add_option("--up", options->up, "Up vector x,y,z in volume axes (default: the patient's head)")
        ->expected(3)->delimiter(',');
    command->add_option("--fov", options->fovDeg, "Vertical field of view in degrees")->capture_default_str();
    command->add_option("--size", options->size, "Image size WIDTHxHEIGHT in pixels")->capture_default_str();
    command->add_option("--iso", options->isoHu, "Iso value in HU")->capture_default_str();
    command->add_option("--step", options->stepVoxels, "March step in voxels")->capture_default_str();
    command->add_option("--bisection-steps", options->bisectionSteps, "Refinement steps of each hit")
        ->capture_default_str();
    command->add_option("--device", options->device,
                        "Vulkan device: index, part of its name, 'cpu' or 'gpu' (default: $CVC_DEVICE, else the best)");
    command->add_flag("--force", options->force, "Replace an existing output file");
    command->callback([options] { runRender(*options); });
}

}  // namespace app
