/// @brief `cvc polyp-check`: the polyp-shape regression suite. Every polyp of a ground truth is
/// seen from poses along its path that put it on a wall, near the missing walls' edge, on their
/// directions and toward a slit tip, for the left, centre and right eyes, through the conformal
/// map, the linear baseline and no map, and measured as the viewer sees it against a pinhole
/// reference, beside what the map alone predicts (engine/studies/polyp_check.h). Writes a
/// Markdown table, JSON and side-by-side crops.
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "app/option_groups.h"
#include "app/option_parsing.h"
#include "app/progress_bar.h"
#include "colon/polyp_shape.h"
#include "distribution/polyp_check_over_ranks.h"
#include "distribution/work_share.h"
#include "engine/core/gpu_context.h"
#include "engine/render/volume_texture.h"
#include "engine/studies/polyp_check_report.h"
#include "engine/studies/polyp_check_request.h"
#include "volumes/load_volume.h"

namespace app {
namespace {

namespace fs = std::filesystem;

struct PolypCheckOptions {
    std::string volumePath;
    std::string rawSpec;
    engine::PolypCheckRequest request;
    std::string candidatesPath;  // --candidates: read as the truth
    std::string outFolder;
    std::string jsonPath;
    std::string wallSize;  // empty: the display's own
    std::string device;
    bool force = false;
};

void runPolypCheck(const PolypCheckOptions& options) {
    engine::PolypCheckRequest request = options.request;
    if (!options.wallSize.empty()) request.wallWidth = parseImageSize(options.wallSize, "--wall-size").first;
    const fs::path folder(options.outFolder);
    // Under mpirun the polyps are dealt out between the ranks; rank 0 checks the folder first.
    distribution::MpiSession& mpi = distribution::mpiSession();

    volumes::LoadOptions load;
    if (!options.rawSpec.empty()) load.raw = volumes::parseRawSpec(options.rawSpec);
    // The request is checked against the display and the truth before the volume loads.
    engine::PolypCheckJob job = engine::polypCheckJobOf(request);
    if (distribution::isReporter(mpi)) {
        engine::requirePolypCheckFolder(folder, options.force);
        if (!options.jsonPath.empty()) requireWritableOutput(options.jsonPath, options.force);
    }
    mpi.barrier();
    const volumes::LoadedVolume loaded = volumes::loadVolumeWithBricks(options.volumePath, load);
    job.toleranceMm = colon::polypToleranceMm(loaded.volume.spacingMm);
    engine::GpuContext context(engine::GpuContextOptions{false, options.device});
    engine::VolumeTexture texture(context, loaded.volume);
    engine::Raycaster raycaster(context, loaded.volume, texture, loaded.bricks);
    std::optional<ProgressBar> progress;
    const auto onProgress = [&progress, &mpi](int done, int total) {
        if (!distribution::isReporter(mpi)) return;  // rank 0 shows its share
        if (!progress) progress.emplace(std::cerr, total, 0, isatty(fileno(stderr)) != 0);
        progress->update(done);
    };
    const nlohmann::json doc = distribution::checkPolypsOverRanks(
        mpi, raycaster, job, request.mapSize, {options.volumePath, request.truthPath, request.warp}, folder / "crops", onProgress);
    if (progress) progress->finish();
    if (!distribution::isReporter(mpi)) return;
    engine::writePolypCheckFiles(folder, doc);
    if (!options.jsonPath.empty()) writeTextFile(options.jsonPath, doc.dump(1) + "\n");

    std::cout << "checked " << job.polypIndices.size() << " polyp(s) x " << doc["plan"]["poses"].size() << " poses x 3 eyes x "
              << job.maps.size() << " maps on " << context.driverDescription() << "; eyes where polyps subtend "
              << doc["plan"]["angular_radius_deg"].get<double>() << " degrees\n";
    std::cout << engine::polypCheckWorstText(doc);
    std::cout << "wrote " << options.outFolder << '\n';
}

}  // namespace

void addPolypCheckCommand(CLI::App& program) {
    auto options = std::make_shared<PolypCheckOptions>();
    CLI::App* command = program.add_subcommand(
        "polyp-check", "Check that polyps keep their shape through the display's map: each seen on a wall, at the "
                       "ceiling's edge, on the ceiling and toward a corner, against a pinhole reference");
    addVolumeOptions(*command, options->volumePath, options->rawSpec);
    auto* truth = command->add_option("--truth", options->request.truthPath,
                                      "Ground truth with polyps and a centreline (cvc phantom's JSON, or cvc insert-polyp's)");
    auto* candidates = command->add_option("--candidates", options->candidatesPath,
                                           "Instead of --truth: cvc candidates' candidates.json (its path too), each "
                                           "candidate checked as a cap of its measured size");
    truth->excludes(candidates);
    candidates->excludes(truth);
    command->add_option("--polyps", options->request.polyps, "Polyps to check, by index in the truth (default: all)")
        ->delimiter(',');
    command->add_option("--poses", options->request.poses,
                        "Poses to check, by name (default: all of the display's; the names are in polyp_check.json)")
        ->delimiter(',');
    command->add_option("--maps", options->request.maps, "Maps to check: conformal (always), linear, none")
        ->delimiter(',')
        ->check(CLI::IsMember({"conformal", "linear", "none"}))
        ->capture_default_str();
    DisplayOptionFields display;
    display.display = &options->request.display;
    display.displayHelp = "Display preset or JSON file with a missing wall";
    display.wallSize = &options->wallSize;
    display.mapSize = &options->request.mapSize;
    display.mapSizeHelp = "Cube-map face size of the baked maps";
    display.warp = &options->request.warp;
    display.mmPerMetre = &options->request.mmPerMetre;
    addDisplayOptions(*command, display);
    command->add_option("--angular-radius", options->request.angularRadiusDeg,
                        "The polyp's angular radius from the eye in degrees, at most: the eye comes as close as the "
                        "map's predicted error at the targeted poses allows (down to 3 degrees)")
        ->check(CLI::Range(1.0, 30.0))
        ->capture_default_str();
    addOutputOptions(*command, options->outFolder, "Output folder", true, options->jsonPath,
                     "Also write the results' JSON to this file", options->force,
                     "Replace an earlier check in the output folder");
    addDeviceOption(*command, options->device);
    command->callback([options] {
        if (options->request.truthPath.empty() == options->candidatesPath.empty()) {
            throw std::invalid_argument("polyp-check needs --truth or --candidates");
        }
        if (!options->candidatesPath.empty()) {
            options->request.truthPath = options->candidatesPath;
            options->request.isCandidateList = true;
        }
        runPolypCheck(*options);
    });
}

}  // namespace app
