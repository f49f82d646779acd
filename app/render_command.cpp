/// @brief `cvc render`: a CT volume from a pinhole camera to a PNG, or every wall of an
/// immersive display for both eyes, at one pose or along a path, into a folder.
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <stdexcept>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "app/option_groups.h"
#include "app/option_parsing.h"
#include "app/render_options.h"
#include "distribution/mpi_session.h"
#include "engine/core/gpu_context.h"
#include "engine/output/hit_image_writer.h"
#include "engine/output/png_writer.h"
#include "engine/render/pinhole_camera.h"
#include "engine/render/raycaster.h"
#include "engine/render/view_rays.h"
#include "engine/render/volume_texture.h"
#include "volumes/dicom_secondary_capture.h"
#include "volumes/load_volume.h"

namespace app {
namespace {

void runPinholeRender(const RenderOptions& options) {
    requireWritableOutput(options.outPath, options.force);
    if (!options.hitsPath.empty()) requireWritableOutput(options.hitsPath, options.force);
    if (!options.dicomOut.empty()) checkDicomOutput(options.dicomOut, options.force);
    if (!options.jsonPath.empty()) requireWritableOutput(options.jsonPath, options.force);
    engine::RenderSettings settings = renderSettingsFrom(options, false);
    settings.isWritingHits = !options.hitsPath.empty();

    const auto start = std::chrono::steady_clock::now();
    volumes::LoadOptions load;
    if (!options.rawSpec.empty()) load.raw = volumes::parseRawSpec(options.rawSpec);
    const volumes::LoadedVolume loaded = volumes::loadVolumeWithBricks(options.volumePath, load);
    const engine::PinholeCamera camera = cameraFrom(options, loaded.volume);

    engine::GpuContext context(engine::GpuContextOptions{false, options.device});
    engine::VolumeTexture texture(context, loaded.volume);
    engine::Raycaster raycaster(context, loaded.volume, texture, loaded.bricks);
    const engine::RenderedImage image = raycaster.render(engine::viewRaysFrom(camera), settings);
    engine::writePng(options.outPath, image.width, image.height, image.rgba, options.force);
    if (!options.hitsPath.empty()) {
        engine::writeHitImageNrrd(options.hitsPath, image.width, image.height, image.hitMm, options.force);
    }

    const double totalS = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    nlohmann::json summary{{"view", "pinhole"},
                           {"renderer", context.driverDescription()},
                           {"width", image.width},
                           {"height", image.height},
                           {"ray_casting_ms", image.deviceMs >= 0.0 ? nlohmann::json(image.deviceMs) : nlohmann::json()},
                           {"seconds", totalS},
                           {"png", std::filesystem::absolute(options.outPath).string()}};
    if (!options.hitsPath.empty()) summary["hits"] = std::filesystem::absolute(options.hitsPath).string();
    std::cout << "rendered " << image.width << "x" << image.height << " on " << context.driverDescription() << ": ";
    if (image.deviceMs >= 0.0) std::cout << "ray casting " << image.deviceMs << " ms, ";
    std::cout << "total " << totalS << " s\nwrote " << options.outPath << '\n';
    if (!options.hitsPath.empty()) std::cout << "wrote " << options.hitsPath << '\n';
    if (!options.dicomOut.empty()) {
        volumes::SecondaryCapture capture;
        capture.identifiers = volumes::dicomIdentifiersOf(options.volumePath);
        capture.seriesInstanceUid = volumes::newDicomUid();
        capture.seriesDescription = "cvc render pinhole view";
        capture.imageComments = "pinhole view";
        std::filesystem::create_directories(options.dicomOut);
        const std::string file = (std::filesystem::path(options.dicomOut) / "render.dcm").string();
        volumes::writeSecondaryCapture(file, image.width, image.height, image.rgba, capture, options.force);
        std::cout << "wrote " << file << '\n';
        summary["dicom"] = std::filesystem::absolute(file).string();
    }
    if (options.isPrintingStats) {
        // A second pass with the counting variant of the shader, so the timed pass is the real one.
        settings.isWritingHits = true;
        settings.isCountingFetches = true;
        const engine::RenderedImage counted = raycaster.render(engine::viewRaysFrom(camera), settings);
        const engine::FetchCounts fetches = engine::fetchCountsOf(counted);
        std::cout << "fetches per ray: mean " << fetches.total / fetches.rays << ", max " << fetches.most << "; "
                  << fetches.total / (image.deviceMs * 1e-3) << " fetches per second\n";
        summary["fetches_per_ray"] = {{"mean", fetches.total / fetches.rays}, {"max", fetches.most}};
    }
    if (!options.jsonPath.empty()) writeTextFile(options.jsonPath, summary.dump(1) + "\n");
}

}  // namespace

void addRenderCommand(CLI::App& program) {
    auto options = std::make_shared<RenderOptions>();
    engine::RenderSettings& s = options->settings;
    CLI::App* command = program.add_subcommand(
        "render", "Render a CT volume: a pinhole view to a PNG, or with --display every wall for both eyes to a folder");
    addVolumeOptions(*command, options->volumePath, options->rawSpec);
    addOutputOptions(*command, options->outPath,
                     "Output: a PNG file (pinhole view, default render.png) or a folder (--display, default frames)",
                     false, options->jsonPath,
                     "Also write a machine-readable summary of the render (what the last lines say) to this file",
                     options->force, "Replace existing output");
    CLI::Option* hits = command->add_option(
        "--hits", options->hitsPath,
        "Also write first-hit positions (volume mm): a pinhole view to this .nrrd file; a display render (no "
        "file name) to frame_NNNN/EYE/WALL_hits.nrrd beside each wall")->expected(0, 1);
    command->add_option("--dicom-out", options->dicomOut,
                        "Also write the pictures into this folder as DICOM Secondary Capture, in the source series' "
                        "study (a source that is not DICOM gets marked placeholder identifiers)");
    command->add_flag("--stats", options->isPrintingStats,
                      "Pinhole view: also print the volume fetches per ray and per second");
    command->add_flag("--resume", options->resume, "Display: keep the finished frames in the folder, render the rest");

    auto* camera = "Camera";
    command->add_option("--position", options->positionMm, "Camera position x,y,z in volume mm")
        ->expected(3)->delimiter(',')->group(camera);
    command->add_option("--look-at", options->lookAtMm, "Point looked at, x,y,z in volume mm (default: centre)")
        ->expected(3)->delimiter(',')->group(camera);
    command->add_option("--up", options->up, "Up vector x,y,z in volume axes (default: the patient's head)")
        ->expected(3)->delimiter(',')->group(camera);
    command->add_option("--fov", options->fovDeg, "Pinhole: vertical field of view in degrees")
        ->capture_default_str()->group(camera);
    command->add_option("--size", options->size, "Pinhole: image size WIDTHxHEIGHT in pixels")
        ->capture_default_str()->group(camera);

    auto* display = "Display";
    DisplayOptionFields displayFields;
    displayFields.display = &options->display;
    displayFields.map = &options->map;
    displayFields.mapSize = &options->mapSize;
    displayFields.mapSizeHelp = "Cube-map texels per face edge of the bake (not with --cube-map, whose file has its size)";
    displayFields.warp = &options->warp;
    displayFields.warpHelp =
        "How the map bends the rays: eye-centred (the map about each eye: each eye sees a conformal image of its own "
        "view), or the warp of space about the map centre (paper Eq. 7) marched as a polyline through five mapped "
        "points of each ray (within a fraction of a pixel of exact), as one chord (the stereo eyes' rays off by "
        "pixels), or exact (every sample mapped: the reference, 4.5 times the time)";
    displayFields.mmPerMetre = &options->mmPerMetre;
    addDisplayOptions(*command, displayFields, display);
    command->add_option("--cube-map", options->cubeMapFile,
                        "Bend the rays through this file from `cvc bake` instead of the cached bake; its box, map "
                        "centre and map must match the display's (after --map), its size replaces --map-size")
        ->group(display);
    command->add_flag("--before-after", options->isWritingBeforeAfter,
                      "Also write before_after.png: the centre eye's walls without and with the map")->group(display);
    addPathOptions(*command,
                   {&options->pathFile,
                    "Centreline: a phantom's JSON ground truth, cvc colon's colon.json, a text file of x y z, or auto "
                    "(run cvc colon on the volume into OUT/colon and fly along its centreline)",
                    false, &options->pathStepMm, &options->smoothingMm, &options->isRetrograde, &options->maxFrames},
                   display);
    command->add_option("--distribute", options->distribution,
                        "Under mpirun: frames (each rank renders whole frames) or walls (each rank renders fixed "
                        "walls of every frame, the cabin cluster's layout)")
        ->check(CLI::IsMember({"frames", "walls"}))->capture_default_str()->group(display);
    command->add_option("--polyp", options->polyp,
                        "One pose on the path from which polyp N of its ground truth is seen ahead and above")
        ->check(CLI::NonNegativeNumber)->group(display);
    command->add_option("--candidates", options->candidatesFile,
                        "cvc candidates' candidates.json (the same --path-step): the review page lists and rings them")
        ->group(display);
    command->add_flag("--at-candidates", options->isAtCandidates,
                      "With --candidates: a frame per candidate (frame N: candidate N + 1), each seen as --polyp is")
        ->group(display);
    command->add_option("--polyp-elevation", options->polypElevationDeg,
                        "Degrees above the horizon ahead at which --polyp is seen (above ~37: on the IC's ceiling; "
                        "past 90: over the head and behind, past ~135 on cave4's missing back wall)")
        ->check(CLI::Range(1.0, 179.0))->capture_default_str()->group(display);
    command->add_option("--polyp-azimuth", options->polypAzimuthDeg,
                        "Degrees to the right of straight up at which --polyp is seen (turns the view about its axis)")
        ->check(CLI::Range(-180.0, 180.0))->capture_default_str()->group(display);

    auto* rendering = "Rendering";
    command->add_option("--mode", options->mode, "iso (first crossing of --iso) or composite (--tf)")
        ->check(CLI::IsMember({"iso", "composite"}))->capture_default_str()->group(rendering);
    command->add_option("--iso", s.isoHu, "Iso value in HU")->capture_default_str()->group(rendering);
    command->add_option("--tf", s.transferFunction, "Transfer function preset: colon-wall, soft-tissue, bone")
        ->capture_default_str()->group(rendering);
    command->add_option_function<double>(
        "--step", [options](const double& value) { options->stepVoxels = value; },
                        "March step in voxels (default: 0.5 for a pinhole view, 1 for display frames)")->group(rendering);
    command->add_option("--refine", s.refinementSteps, "Bisection steps refining each iso hit (0: none)")
        ->capture_default_str()->group(rendering);
    command->add_option("--filter", options->filter, "trilinear (fast) or tricubic (B-spline, for stills)")
        ->check(CLI::IsMember({"trilinear", "tricubic"}))->capture_default_str()->group(rendering);
    command->add_option("--gradient", options->gradient,
                        "Shading normals: bspline (central differences of the cubic B-spline: smooth on coarse CT, 48 "
                        "fetches per shaded sample), bspline-voxels (the B-spline's values at the voxels, blended "
                        "trilinearly from the gradient volume: its smoothing in 1 fetch) or central (of the trilinear "
                        "interpolant: 6 fetches); default: bspline-voxels for a pinhole view, central for display "
                        "frames; tricubic always uses bspline")
        ->check(CLI::IsMember({"bspline", "bspline-voxels", "central"}))->group(rendering);
    command->add_option("--gradient-volume", options->gradientVolume,
                        "on (default): shade with gradients read from a gradient volume computed once (1 fetch per "
                        "shaded sample, 8 with bspline; 8 bytes of device memory a voxel); off: from the volume's own "
                        "taps (6, or 48 with bspline and bspline-voxels); the same normals but for rounding "
                        "(bspline-voxels off takes the B-spline's own)")
        ->check(CLI::IsMember({"on", "off"}))->group(rendering);
    command->add_flag("--no-skip", options->isSkippingOff, "Turn off empty-space skipping")->group(rendering);
    command->add_flag("--no-start-pass", options->isStartPassOff,
                      "Skip empty space in the march only, without the pass over 8x8 tiles that starts rays past it")
        ->group(rendering);
    command->add_flag("--look-in-every-tile", s.isLookingInEveryTile,
                      "Keep the march's looks at the empty-space map in every tile, not only where the tile pass "
                      "finds room to skip ahead (the same samples; for benchmarks)")
        ->group(rendering);
    command->add_flag("--skip-bent-rays", s.isSkippingBentRays,
                      "--warp exact: skip empty space along the bent rays too, by the map's speed bound "
                      "(slower on lavapipe; docs/benchmarks/march.md)")
        ->group(rendering);
    command->add_option("--skip-cell", s.skipCellVoxels, "Edge in voxels of the empty-space map's cells (8: the 8^3 bricks)")
        ->check(CLI::Range(1, 64))->capture_default_str()->group(rendering);
    command->add_option("--early-termination", s.earlyTerminationOpacity,
                        "Composite mode: stop a ray once its opacity reaches this")
        ->check(CLI::Range(0.01, 1.0))->capture_default_str()->group(rendering);
    command->add_flag("--adaptive", s.isAdaptive, "Lengthen steps where a pixel covers more than a voxel")
        ->group(rendering);
    command->add_option("--jitter", s.jitterSeed, "Jitter ray starts with this seed (same seed, same image)")
        ->each([&s](const std::string&) { s.isJittered = true; })->group(rendering);
    command->add_option_function<double>(
        "--light-distance", [options](const double& value) { options->lightHalfDistanceMm = value; },
                        "Distance in mm at which the headlight is half as bright (0: no falloff; default: none for "
                        "a pinhole view, 25 for a display)")->group(rendering);
    addDeviceOption(*command, options->device);
    command->callback([options, hits, command] {
        refuseRenderOptionsNotApplying(*command, *options);
        if (options->display.empty()) {
            if (hits->count() > 0 && options->hitsPath.empty()) {
                throw std::invalid_argument("--hits needs a file name for a pinhole view (e.g. --hits hits.nrrd)");
            }
            if (options->outPath.empty()) options->outPath = "render.png";
            if (distribution::mpiSession().isShared()) {
                throw std::invalid_argument("a pinhole view is one image: under mpirun give --display to share frames");
            }
            runPinholeRender(*options);
        } else {
            if (!options->hitsPath.empty()) {
                throw std::invalid_argument("--hits takes no file name for a display render: the hit images go beside "
                                            "each wall's PNG");
            }
            if (command->count("--distribute") > 0 && !distribution::mpiSession().isShared()) {
                std::cerr << "cvc: warning: --distribute splits the work between mpirun's ranks; this one process "
                             "renders all of it\n";
            }
            options->isWritingDisplayHits = hits->count() > 0;
            if (options->outPath.empty()) options->outPath = "frames";
            runDisplayRender(*options);
        }
    });
}

}  // namespace app
