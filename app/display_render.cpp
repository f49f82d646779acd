/// @brief `cvc render --display`: every wall of an immersive display for both eyes, at one
/// pose or along a path, bent through the display's map. The engine renders the sequence
/// (engine/display/frame_sequence.h); this file turns options into a job, shows progress and
/// passes Ctrl-C in as a cancel request.
#include <atomic>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>

#include <unistd.h>

#include "app/colon_command.h"
#include "app/option_parsing.h"
#include "app/progress_bar.h"
#include "app/render_options.h"
#include "conformal/cube_map_baker.h"
#include "engine/core/gpu_context.h"
#include "engine/display/camera_path.h"
#include "engine/display/display_json.h"
#include "engine/display/display_map.h"
#include "engine/display/frame_sequence.h"
#include "engine/display/review_page.h"
#include "engine/render/volume_texture.h"
#include "volumes/load_volume.h"

namespace app {
namespace {

std::atomic<bool> gInterruptRequested{false};

extern "C" void onInterrupt(int) {
    gInterruptRequested = true;
    std::signal(SIGINT, SIG_DFL);  // a second Ctrl-C stops at once
}

/// Installs the Ctrl-C handler for the lifetime of a sequence and restores the old one.
class InterruptGuard {
public:
    InterruptGuard() : mPrevious(std::signal(SIGINT, onInterrupt)) { gInterruptRequested = false; }
    ~InterruptGuard() { std::signal(SIGINT, mPrevious); }
    InterruptGuard(const InterruptGuard&) = delete;
    InterruptGuard& operator=(const InterruptGuard&) = delete;

private:
    void (*mPrevious)(int);
};

/// The poses asked for: beneath a polyp, along a path, or the one given by --position.
std::vector<engine::CameraPose> posesFrom(const RenderOptions& options) {
    engine::PoseRequest request;
    request.pathFile = options.pathFile;
    request.path.stepMm = options.pathStepMm;
    request.path.smoothingMm = options.smoothingMm;
    request.path.direction = options.isRetrograde ? engine::Direction::Retrograde : engine::Direction::Antegrade;
    request.maxFrames = options.maxFrames;
    request.polyp = options.polyp;
    request.polypElevationDeg = options.polypElevationDeg;
    if (!options.positionMm.empty()) request.positionMm = vec3From(options.positionMm, "--position");
    if (!options.lookAtMm.empty()) request.lookAtMm = vec3From(options.lookAtMm, "--look-at");
    if (!options.up.empty()) request.up = vec3From(options.up, "--up");
    return engine::posesFor(request);
}

/// `--path auto`: the colon analysis of the volume in OUT/colon/ (reused on --resume), and the
/// options that fly along its centreline, through the cleansed volume where fluid was cleansed.
RenderOptions withAutomaticPath(const RenderOptions& given) {
    RenderOptions options = given;
    ColonRequest request;
    request.volumePath = given.volumePath;
    request.rawSpec = given.rawSpec;
    request.outFolder = (std::filesystem::path(given.outPath) / "colon").string();
    request.force = given.force;
    request.resume = given.resume;
    const ColonOutputs outputs = runColonAnalysis(request);
    options.pathFile = outputs.colonJson;
    if (!outputs.cleansedNrrd.empty()) {
        options.volumePath = outputs.cleansedNrrd;
        options.rawSpec.clear();
    }
    return options;
}

}  // namespace

void runDisplayRender(const RenderOptions& givenOptions) {
    // --path auto writes its analysis into the output folder: refuse an occupied folder first,
    // by the sequence's own rule (a resumed folder is checked against its manifest later, once
    // the poses are known).
    const bool isAutomaticPath = givenOptions.pathFile == "auto";
    if (isAutomaticPath && !givenOptions.resume) {
        engine::checkSequenceOutput(engine::SequenceJob{}, {givenOptions.outPath, givenOptions.force, false, {}});
    }
    const RenderOptions options = isAutomaticPath ? withAutomaticPath(givenOptions) : givenOptions;
    engine::Display display = engine::loadDisplay(options.display);
    if (!options.map.empty()) display.map = conformal::mapKindFromName(options.map);
    engine::validateDisplay(display);
    if (!(options.mmPerMetre > 0.0 && options.mmPerMetre <= 1000.0)) {
        throw std::invalid_argument("--scale must be in (0, 1000] mm per metre");
    }
    if (options.mapSize < 16 || options.mapSize > 4096) throw std::invalid_argument("--map-size must be 16..4096");

    engine::SequenceJob job;
    job.volumePath = options.volumePath;
    job.display = display;
    job.poses = posesFrom(options);
    job.mmPerMetre = options.mmPerMetre;
    job.settings = renderSettingsFrom(options, true);
    job.warpMode = options.warp == "exact" ? engine::WarpMode::Exact : engine::WarpMode::Chord;
    job.isWritingBeforeAfter = options.isWritingBeforeAfter;
    job.isWritingHits = options.isWritingDisplayHits;
    job.mapSource = display.map == conformal::MapKind::None ? "none"
                    : options.cubeMapFile.empty()
                        ? "baked, " + std::to_string(options.mapSize) + "^2 per face"
                        : std::filesystem::absolute(options.cubeMapFile).string();

    engine::SequenceOutput output{options.outPath, options.force, options.resume, {}};
    if (isAutomaticPath) output.companions = {"colon"};
    engine::checkSequenceOutput(job, output);  // before the volume loads: a refusal comes at once

    volumes::LoadOptions load;
    if (!options.rawSpec.empty()) load.raw = volumes::parseRawSpec(options.rawSpec);
    const volumes::LoadedVolume loaded = volumes::loadVolumeWithBricks(options.volumePath, load);
    engine::GpuContext context(engine::GpuContextOptions{false, options.device});
    job.rendererDescription = context.driverDescription();
    engine::VolumeTexture texture(context, loaded.volume);
    engine::Raycaster raycaster(context, loaded.volume, texture, loaded.bricks);
    // A --cube-map for a display without a map goes to cubeMapFor too, which refuses it: never ignored.
    if (display.map != conformal::MapKind::None || !options.cubeMapFile.empty()) {
        conformal::BakeReport report;
        const conformal::CubeMap map = engine::cubeMapFor(display, options.mapSize, options.cubeMapFile, &report);
        const std::string origin = !options.cubeMapFile.empty() ? "from " + options.cubeMapFile
                                   : report.wasLoadedFromCache
                                       ? "loaded from " + report.cachePath.string()
                                       : "computed in " + std::to_string(report.mapSeconds + report.bakeSeconds) + " s";
        std::cerr << "map: " << conformal::mapKindName(map.kind) << ", " << map.size << "^2 per face, " << origin
                  << '\n';
        raycaster.setCubeMap(map.size, map.rgba);
    }

    InterruptGuard interruptGuard;
    std::optional<ProgressBar> progress;  // made at the first report, which says how many frames were kept
    engine::SequenceHooks hooks;
    hooks.isCancelled = [] { return gInterruptRequested.load(); };
    hooks.onProgress = [&progress](int done, int total) {
        if (!progress) progress.emplace(std::cerr, total, done, isatty(fileno(stderr)) != 0);
        progress->update(done);
    };
    engine::SequenceSummary summary;
    try {
        summary = engine::renderSequence(raycaster, job, output, hooks);
    } catch (...) {
        if (progress) progress->finish();
        throw;
    }
    if (progress) progress->finish();
    // After the sequence, so that a resumed run's page covers the frames kept and the new ones.
    engine::writeReviewPage(options.outPath, engine::reviewPageOfSequence(job, &loaded.volume));
    const int images = summary.framesRendered * 2 * static_cast<int>(display.walls.size());
    std::cout << "rendered " << summary.framesRendered << " frame(s) (" << images << " wall images) on "
              << context.driverDescription() << " in " << summary.seconds << " s";
    if (summary.framesRendered > 0) {
        std::cout << ", " << summary.seconds / summary.framesRendered << " s per frame (ray casting "
                  << summary.rayCastingMs / summary.framesRendered << " ms of device time per stereo frame)";
    }
    if (summary.framesKept > 0) std::cout << "; kept " << summary.framesKept << " finished frame(s)";
    std::cout << "\nwrote " << options.outPath << " (review page: "
              << (std::filesystem::path(options.outPath) / "index.html").string() << ")\n";
}

}  // namespace app
