/// @brief `cvc coverage`: how much of the colon wall a fly-through shows the reader, per
/// display. The colon is found by the colon analysis, its wall meshed at the render's iso value
/// (colon/wall_surface.h), the fly-through rendered from the centre eye and every pixel's first
/// hit marked on the wall (colon/surface_coverage.h, engine/studies/coverage_run.h). Writes the
/// percentage, the unseen patches largest first with a pose that shows each, pictures of them
/// and a review page; `--compare` runs the table of displays and maps on one path.
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
#include "distribution/coverage_over_ranks.h"
#include "distribution/work_share.h"
#include "engine/core/gpu_context.h"
#include "engine/display/display_json.h"
#include "engine/render/volume_texture.h"
#include "engine/studies/coverage_study.h"

namespace app {
namespace {

namespace fs = std::filesystem;

struct CoverageOptions {
    engine::CoverageStudySettings study;  // the volume, path, thresholds and patches
    std::string display = "ic5";
    std::string map;  // empty: the display's own
    bool isRetrograde = false;
    bool isBothDirections = false;
    std::string wallSize;  // empty: the display's own (with --compare: kCompareWallSize)
    int mapSize = 1024;
    std::string warp = "eye-centred";
    bool isCompare = false;
    std::string outFolder;
    std::string jsonPath;
    bool force = false;
    std::string device;
};

/// The reduced wall size of --compare: a quarter of the cabin's 1400-pixel walls across, so the
/// six rows run in minutes on a CPU; docs/coverage.md shows how full size changes a row.
constexpr const char* kCompareWallSize = "350x262";

/// Renders one row, measures its coverage and writes its folder; returns its JSON summary (on
/// rank 0; null elsewhere). Progress goes to stderr, the row's result line to stdout.
nlohmann::json runRow(const CoverageOptions& options, const engine::CoverageRow& row, const engine::CoverageScene& scene,
                      engine::Raycaster& raycaster, const std::string& rendererDescription, const fs::path& folder) {
    std::optional<ProgressBar> progress;
    distribution::CoverageReport report;
    report.say = [](const std::string& line) { std::cerr << line << '\n'; };
    report.onProgress = [&progress](int done, int total) {
        if (!progress) progress.emplace(std::cerr, total, done, isatty(fileno(stderr)) != 0);
        progress->update(done);
    };
    report.onFramesDone = [&progress] {
        if (progress) progress->finish();
        progress.reset();
    };
    report.tell = [](const std::string& line) { std::cout << line << '\n'; };
    return distribution::coverageRowOverRanks(distribution::mpiSession(), options.study, row, scene, raycaster,
                                              options.mapSize, rendererDescription, folder, report);
}

engine::Display rowDisplay(const std::string& name, const std::string& map, const std::string& wallSize) {
    const int width = wallSize.empty() ? 0 : parseImageSize(wallSize, "--wall-size").first;
    return engine::coverageRowDisplay(name, map, width);
}

std::vector<engine::CoverageRow> rowsOf(const CoverageOptions& options) {
    using Directions = engine::CoverageDirections;
    if (!options.isCompare) {
        const Directions directions = options.isBothDirections ? Directions::Both
                                      : options.isRetrograde   ? Directions::Retrograde
                                                               : Directions::Antegrade;
        engine::Display display = rowDisplay(options.display, options.map, options.wallSize);
        return {{display.name, display, directions}};
    }
    const std::string size = options.wallSize.empty() ? kCompareWallSize : options.wallSize;
    return {{"row_1_forward_antegrade", rowDisplay("forward", "", size), Directions::Antegrade},
            {"row_2_forward_both", rowDisplay("forward", "", size), Directions::Both},
            {"row_3_ic5_none", rowDisplay("ic5", "none", size), Directions::Antegrade},
            {"row_4_ic5_linear", rowDisplay("ic5", "linear", size), Directions::Antegrade},
            {"row_5_ic5_conformal", rowDisplay("ic5", "conformal", size), Directions::Antegrade},
            {"row_6_ic6", rowDisplay("ic6", "", size), Directions::Antegrade}};
}

void validate(const CoverageOptions& options) {
    if (options.isRetrograde && options.isBothDirections) {
        throw std::invalid_argument("--retrograde and --both-directions exclude each other");
    }
    engine::validateCoverageStudySettings(options.study, options.mapSize);
}

void runCoverageCommand(const CoverageOptions& givenOptions) {
    // Under mpirun every rank analyses the same volume (the same wall, element for element) and
    // flies its share of each row's frames; rank 0 prepares the folder, merges and reports.
    distribution::MpiSession& mpi = distribution::mpiSession();
    CoverageOptions options = givenOptions;
    options.study.warpMode = engine::warpModeFromName(options.warp);
    validate(options);
    const std::vector<engine::CoverageRow> rows = rowsOf(options);  // a bad display fails before anything loads
    if (distribution::isReporter(mpi)) {
        engine::prepareCoverageFolder(options.outFolder, options.force);
        if (!options.jsonPath.empty()) requireWritableOutput(options.jsonPath, options.force);
    }
    mpi.barrier();

    const engine::CoverageScene scene = engine::prepareCoverageScene(options.study, [&mpi](const std::string& line) {
        if (distribution::isReporter(mpi)) std::cerr << line << '\n';  // one voice for the job under mpirun
    });
    engine::GpuContext context(engine::GpuContextOptions{false, options.device});
    engine::VolumeTexture texture(context, scene.loaded.volume);
    engine::Raycaster raycaster(context, scene.loaded.volume, texture, scene.loaded.bricks);

    const fs::path folder(options.outFolder);
    nlohmann::json summary;
    if (!options.isCompare) {
        summary = runRow(options, rows.front(), scene, raycaster, context.driverDescription(), folder);
    } else {
        summary["wall_size"] = options.wallSize.empty() ? kCompareWallSize : options.wallSize;
        summary["path_step_mm"] = options.study.pathStepMm;
        summary["volume"] = fs::absolute(options.study.volumePath).string();
        summary["rows"] = nlohmann::json::array();
        std::string table = engine::coverageCompareHeader();
        for (const engine::CoverageRow& row : rows) {
            const nlohmann::json result = runRow(options, row, scene, raycaster, context.driverDescription(), folder / row.name);
            if (!distribution::isReporter(mpi)) continue;
            summary["rows"].push_back(engine::coverageCompareEntry(row.name, result));
            table += engine::coverageCompareLine(row.name, result);
        }
        if (distribution::isReporter(mpi)) {
            writeTextFile((folder / "compare.json").string(), summary.dump(1) + "\n");
            writeTextFile((folder / "compare.md").string(), table);
            std::cout << table;
        }
    }
    if (!distribution::isReporter(mpi)) return;
    if (!options.jsonPath.empty()) writeTextFile(options.jsonPath, summary.dump(1) + "\n");
    std::cout << "wrote " << options.outFolder << '\n';
}

}  // namespace

void addCoverageCommand(CLI::App& program) {
    auto options = std::make_shared<CoverageOptions>();
    CLI::App* command = program.add_subcommand(
        "coverage", "Measure how much of the colon wall a fly-through shows on a display, and where the unseen "
                    "patches are; --compare runs the table of displays and maps");
    addVolumeOptions(*command, options->study.volumePath, options->study.rawSpec);
    addPathOptions(*command, {&options->study.pathFile,
                              "Centreline: a phantom's JSON ground truth, cvc colon's colon.json, a text file of x y z, or "
                              "auto (the colon analysis's own)",
                              true, &options->study.pathStepMm, &options->study.smoothingMm, &options->isRetrograde,
                              &options->study.maxFrames, "At most this many frames per direction"});
    command->add_flag("--both-directions", options->isBothDirections, "Fly antegrade, then retrograde");
    DisplayOptionFields display;
    display.display = &options->display;
    display.map = &options->map;
    display.wallSize = &options->wallSize;  // with --compare: kCompareWallSize unless given
    display.mapSize = &options->mapSize;
    display.warp = &options->warp;
    display.warpHelp = "eye-centred, polyline, chord or exact (the centre eye's rays: all but exact are one chord)";
    display.mmPerMetre = &options->study.mmPerMetre;
    addDisplayOptions(*command, display);
    command->add_option("--iso", options->study.isoHu, "Iso value in HU of the wall (rendered and meshed)")->capture_default_str();
    command->add_option("--max-footprint", options->study.coverage.maxFootprintMm2,
                        "Largest wall area per pixel, mm^2, for a pixel to count")->capture_default_str();
    command->add_option("--max-angle", options->study.coverage.maxViewAngleDeg,
                        "Largest angle between the wall's normal and the view, degrees")->capture_default_str();
    command->add_option("--min-patch", options->study.minPatchMm2, "Smallest unseen patch reported, mm^2")->capture_default_str();
    command->add_option("--patch-pictures", options->study.patchPictures, "Pictures (and poses) for this many largest patches")
        ->capture_default_str();
    command->add_flag("--compare", options->isCompare,
                      "Run the table: forward antegrade, forward both directions, ic5 without a map, linear and "
                      "conformal, ic6; one subfolder per row");
    addOutputOptions(*command, options->outFolder, "Output folder", true, options->jsonPath,
                     "Also write the summary JSON to this file", options->force,
                     "Replace an earlier coverage run in the output folder");
    addDeviceOption(*command, options->device);
    command->callback([options, command] {
        if (options->isCompare) {
            refuseGivenOptions(*command, {"--display", "--map", "--retrograde", "--both-directions"},
                               "is set by each row of --compare itself");
        } else {
            refuseMapOptionsWithoutMap(*command, options->display, options->map);
        }
        runCoverageCommand(*options);
    });
}

}  // namespace app
