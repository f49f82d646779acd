/// @brief `cvc render --display`: every wall of an immersive display for both eyes, at one
/// pose or along a path, bent through the display's map. The engine renders the sequence
/// (engine/sequence/frame_sequence.h); this file turns options into a job, shows progress and
/// passes Ctrl-C in as a cancel request.
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "app/colon_command.h"
#include "app/interrupt_guard.h"
#include "app/option_parsing.h"
#include "app/progress_bar.h"
#include "app/render_options.h"
#include "conformal/cube_map_baker.h"
#include "conformal/cube_map_speed.h"
#include "distribution/mpi_session.h"
#include "distribution/sequence_over_ranks.h"
#include "distribution/work_share.h"
#include "engine/core/gpu_context.h"
#include "engine/display/display_json.h"
#include "engine/display/display_map.h"
#include "engine/render/volume_texture.h"
#include "engine/sequence/camera_path.h"
#include "engine/sequence/frame_sequence.h"
#include "engine/sequence/sequence_dicom.h"
#include "engine/sequence/sequence_review_page.h"
#include "engine/studies/candidate_study.h"
#include "volumes/load_volume.h"

namespace app {
namespace {

/// The poses asked for: toward a polyp or each candidate, along a path, or the one of --position.
std::vector<engine::CameraPose> posesFrom(const RenderOptions& options) {
    engine::PoseRequest request;
    request.pathFile = options.pathFile;
    request.path.stepMm = options.pathStepMm;
    request.path.smoothingMm = options.smoothingMm;
    request.path.direction = options.isRetrograde ? engine::Direction::Retrograde : engine::Direction::Antegrade;
    request.maxFrames = options.maxFrames;
    request.polyp = options.polyp;
    if (options.isAtCandidates) request.candidatesFile = options.candidatesFile;
    request.polypElevationDeg = options.polypElevationDeg;
    request.polypAzimuthDeg = options.polypAzimuthDeg;
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

/// Rank 0's reading of the request (every rank of one process).
distribution::SequenceRequest readRequest(const RenderOptions& givenOptions, RenderOptions& options) {
    // --path auto writes its analysis into the output folder: refuse an occupied folder first,
    // by the sequence's own rule (a resumed folder is checked against its manifest later, once
    // the poses are known).
    const bool isAutomaticPath = givenOptions.pathFile == "auto";
    if (isAutomaticPath && !givenOptions.resume) {
        engine::checkSequenceOutput(engine::SequenceJob{}, {givenOptions.outPath, givenOptions.force, false, {}});
    }
    options = isAutomaticPath ? withAutomaticPath(givenOptions) : givenOptions;
    distribution::SequenceRequest request;
    request.volumePath = options.volumePath;
    request.display = engine::loadDisplay(options.display);
    if (!options.map.empty()) request.display.map = conformal::mapKindFromName(options.map);
    engine::validateDisplay(request.display);
    request.poses = posesFrom(options);
    return request;
}

}  // namespace

void runDisplayRender(const RenderOptions& givenOptions) {
    // Under mpirun rank 0 alone reads the display and the path (and runs the colon analysis for
    // --path auto); every rank gets what it found.
    distribution::MpiSession& mpi = distribution::mpiSession();
    if (!givenOptions.jsonPath.empty() && distribution::isReporter(mpi)) {
        requireWritableOutput(givenOptions.jsonPath, givenOptions.force);
    }
    RenderOptions options = givenOptions;
    const distribution::SequenceRequest request =
        distribution::sharedSequenceRequest(mpi, [&] { return readRequest(givenOptions, options); });
    if (options.volumePath != request.volumePath) {  // another rank's: the cleansed NRRD of --path auto
        options.volumePath = request.volumePath;
        options.rawSpec.clear();
    }
    const bool isAutomaticPath = givenOptions.pathFile == "auto";
    const engine::Display& display = request.display;
    if (!(options.mmPerMetre > 0.0 && options.mmPerMetre <= 1000.0)) {
        throw std::invalid_argument("--scale must be in (0, 1000] mm per metre");
    }
    if (options.mapSize < 16 || options.mapSize > 4096) throw std::invalid_argument("--map-size must be 16..4096");

    engine::SequenceJob job;
    job.volumePath = options.volumePath;
    job.display = display;
    job.poses = request.poses;
    job.mmPerMetre = options.mmPerMetre;
    job.settings = renderSettingsFrom(options, true);
    job.warpMode = engine::warpModeFromName(options.warp);
    job.isWritingBeforeAfter = options.isWritingBeforeAfter;
    job.isWritingHits = options.isWritingDisplayHits;
    job.mapSource = display.map == conformal::MapKind::None ? "none"
                    : options.cubeMapFile.empty()
                        ? "baked, " + std::to_string(options.mapSize) + "^2 per face"
                        : std::filesystem::absolute(options.cubeMapFile).string();

    engine::SequenceOutput output{options.outPath, options.force, options.resume, {}};
    if (isAutomaticPath) output.companions = {"colon"};
    engine::checkSequenceOutput(job, output);  // before the volume loads: a refusal comes at once
    if (!options.dicomOut.empty()) checkDicomOutput(options.dicomOut, options.force);
    std::vector<engine::ReviewCandidate> candidates;  // --candidates: listed, and ringed on the frames rendered here
    if (!options.candidatesFile.empty()) {
        candidates = engine::reviewCandidatesOf(options.candidatesFile, options.outPath, static_cast<int>(job.poses.size()),
                                                options.isAtCandidates ? 0.0 : options.pathStepMm);
    }

    volumes::LoadOptions load;
    if (!options.rawSpec.empty()) load.raw = volumes::parseRawSpec(options.rawSpec);
    const volumes::LoadedVolume loaded = volumes::loadVolumeWithBricks(options.volumePath, load);
    engine::GpuContext context(engine::GpuContextOptions{false, options.device});
    job.rendererDescription = context.driverDescription();
    engine::VolumeTexture texture(context, loaded.volume);
    engine::Raycaster raycaster(context, loaded.volume, texture, loaded.bricks);
    // A --cube-map for a display without a map goes to cubeMapFor too, which refuses it: never ignored.
    // Rank 0 bakes (or finds) the map first; the others then load it from the cache it filled.
    const bool hasMap = display.map != conformal::MapKind::None || !options.cubeMapFile.empty();
    const auto loadMap = [&] {
        conformal::BakeReport report;
        const conformal::CubeMap map = engine::cubeMapFor(display, options.mapSize, options.cubeMapFile, &report);
        const std::string origin = !options.cubeMapFile.empty() ? "from " + options.cubeMapFile
                                   : report.wasLoadedFromCache
                                       ? "loaded from " + report.cachePath.string()
                                       : "computed in " + std::to_string(report.mapSeconds + report.bakeSeconds) + " s";
        if (distribution::isReporter(mpi)) {
            std::cerr << "map: " << conformal::mapKindName(map.kind) << ", " << map.size << "^2 per face, " << origin
                      << '\n';
        }
        raycaster.setCubeMap(map.size, map.rgba);
        if (job.settings.isSkippingBentRays && job.warpMode == engine::WarpMode::Exact) {
            const conformal::SpeedBoundMap bounds = conformal::speedBoundMap(map.size, map.rgba);
            raycaster.setSpeedBounds(bounds.size, bounds.rgba);
        }
    };
    distribution::rootFirst(mpi, [&] {
        if (hasMap) loadMap();
    });

    InterruptGuard interruptGuard;
    std::optional<ProgressBar> progress;  // made at the first report, which says how many frames were kept
    engine::SequenceHooks hooks;
    hooks.isCancelled = [] { return InterruptGuard::isRequested(); };
    hooks.onProgress = [&progress](int done, int total) {
        if (!progress) progress.emplace(std::cerr, total, done, isatty(fileno(stderr)) != 0);
        progress->update(done);
    };
    if (!options.candidatesFile.empty()) {
        job.isComputingHits = true;
        hooks.onFrame = [&](int frame, const auto& walls) { engine::ringCandidatesOnFrame(candidates, frame, display, walls); };
    }
    const engine::Distribution sharing =
        options.distribution == "walls" ? engine::Distribution::Walls : engine::Distribution::Frames;
    engine::SequenceSummary summary;
    try {
        summary = distribution::renderSequenceOverRanks(mpi, raycaster, job, output, hooks, sharing);
    } catch (...) {
        if (progress) progress->finish();
        throw;
    }
    if (progress) progress->finish();
    if (!distribution::isReporter(mpi)) return;  // rank 0 writes the page and speaks for the job
    // After the sequence, so that a resumed run's page covers the frames kept and the new ones.
    engine::ReviewPage page = engine::reviewPageOfSequence(job, &loaded.volume);
    page.candidates = std::move(candidates);
    engine::writeReviewPage(options.outPath, page);
    nlohmann::json document = engine::sequenceSummaryJson(job, summary, options.outPath);
    if (!options.dicomOut.empty()) {
        // The source's identifiers: the folder given, not the cleansed NRRD that --path auto renders.
        const engine::SequenceDicomSummary dicom = engine::writeSequenceDicom(
            job, options.outPath, options.dicomOut, volumes::dicomIdentifiersOf(givenOptions.volumePath), options.force);
        std::cerr << "dicom: " << dicom.files << " file(s) in " << dicom.series << " series in " << options.dicomOut << '\n';
        document["dicom"] = {{"folder", std::filesystem::absolute(options.dicomOut).string()},
                             {"files", dicom.files},
                             {"series", dicom.series}};
    }
    const int images = document.at("wall_images").get<int>();
    std::cout << "rendered " << summary.framesRendered << " frame(s) (" << images << " wall images) on "
              << context.driverDescription();
    if (mpi.isShared()) std::cout << " x " << mpi.ranks() << " ranks (" << options.distribution << ")";
    std::cout << " in " << summary.seconds << " s";
    if (summary.framesRendered > 0) {
        std::cout << ", " << summary.seconds / summary.framesRendered << " s per frame (ray casting "
                  << summary.rayCastingMs / summary.framesRendered << " ms of device time per stereo frame)";
    }
    if (summary.sheetsOfOtherRanks > 0) {
        std::cout << "; rank 0 wrote " << summary.sheetsOfOtherRanks << " sheet(s) of other ranks' walls in "
                  << summary.sheetsOfOtherRanksSeconds << " s";
    }
    if (summary.framesKept > 0) std::cout << "; kept " << summary.framesKept << " finished frame(s)";
    if (!summary.framesLeftHalfWritten.empty()) {
        std::cout << "; the run that stopped was writing frame(s)";
        for (int index : summary.framesLeftHalfWritten) std::cout << ' ' << index;
        std::cout << ", rendered again";
    }
    if (!summary.framesFinishedFromImages.empty()) {
        std::cout << "; finished frame(s)";
        for (int index : summary.framesFinishedFromImages) std::cout << ' ' << index;
        std::cout << " from the images the run that stopped had written";
    }
    if (!options.jsonPath.empty()) {
        document["view"] = "display";
        document["ranks"] = mpi.ranks();
        // Each rank times its own dispatches: under mpirun rank 0's alone are known here.
        if (mpi.isShared()) document["ray_casting_ms_per_stereo_frame"] = nullptr;
        writeTextFile(options.jsonPath, document.dump(1) + "\n");
    }
    std::cout << "\nwrote " << options.outPath << " (review page: "
              << (std::filesystem::path(options.outPath) / "index.html").string() << ")\n";
}

}  // namespace app
