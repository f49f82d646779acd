/// @brief `cvc polyp-check`: the polyp-shape regression suite. Every polyp of a ground truth is
/// seen from poses along its path that put it on a wall, near the missing walls' edge, on their
/// directions and toward a slit tip, for the left, centre and right eyes, through the conformal
/// map, the linear baseline and no map, and measured as the viewer sees it against a pinhole
/// reference, beside what the map alone predicts (engine/studies/polyp_check.h). Writes a
/// Markdown table, JSON and side-by-side crops.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <tuple>

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "app/option_groups.h"
#include "app/option_parsing.h"
#include "app/progress_bar.h"
#include "colon/polyp_truth.h"
#include "distribution/work_share.h"
#include "engine/core/gpu_context.h"
#include "engine/display/display_json.h"
#include "engine/display/display_map.h"
#include "engine/render/volume_texture.h"
#include "engine/studies/polyp_check.h"
#include "engine/studies/polyp_check_report.h"
#include "volumes/load_volume.h"

namespace app {
namespace {

namespace fs = std::filesystem;

struct PolypCheckOptions {
    std::string volumePath;
    std::string rawSpec;
    std::string truthPath;
    std::string display = "ic5";
    std::vector<int> polyps;  // empty: every polyp of the truth
    std::vector<std::string> poses;  // empty: every pose of the display
    std::vector<std::string> maps{"conformal", "linear", "none"};
    std::string outFolder;
    std::string jsonPath;
    std::string wallSize;  // empty: the display's own
    int mapSize = 1024;
    double mmPerMetre = 10.0;
    std::string warp = "eye-centred";
    double angularRadiusDeg = 5.0;
    std::string device;
    bool force = false;
};

void runPolypCheck(const PolypCheckOptions& options) {
    engine::Display display = engine::loadDisplay(options.display);
    if (!options.wallSize.empty()) resizeWalls(display, options.wallSize);
    engine::validateDisplay(display);
    if (display.map == conformal::MapKind::None) {
        throw std::invalid_argument("display '" + display.name + "' has no map to check (it misses no wall)");
    }
    if (!(options.mmPerMetre > 0.0 && options.mmPerMetre <= 1000.0)) {
        throw std::invalid_argument("--scale must be in (0, 1000] mm per metre");
    }
    if (options.mapSize < 16 || options.mapSize > 4096) throw std::invalid_argument("--map-size must be 16..4096");
    const fs::path folder(options.outFolder);
    const fs::path jsonFile = folder / "polyp_check.json", tableFile = folder / "polyp_check.md", crops = folder / "crops";
    // Under mpirun the polyps are dealt out between the ranks; rank 0 checks the folder first.
    distribution::MpiSession& mpi = distribution::mpiSession();
    if (distribution::isReporter(mpi)) {
        if (fs::exists(folder) && !fs::is_directory(folder)) throw std::runtime_error(options.outFolder + ": is not a folder");
        if (!options.force && (fs::exists(jsonFile) || fs::exists(tableFile) || fs::exists(crops))) {
            throw std::runtime_error(options.outFolder + ": holds an earlier polyp check (use --force to replace it)");
        }
        if (!options.jsonPath.empty()) requireWritableOutput(options.jsonPath, options.force);
    }
    mpi.barrier();

    engine::PolypCheckJob job;
    job.display = display;
    job.polyps = colon::readPolypTruth(options.truthPath);
    job.centreline = engine::readCentreline(options.truthPath);
    if (job.centreline.anterior) job.path.initialUp = *job.centreline.anterior;
    if (options.polyps.empty()) {
        for (int i = 0; i < static_cast<int>(job.polyps.size()); ++i) job.polypIndices.push_back(i);
    } else {
        job.polypIndices = options.polyps;
    }
    job.mmPerMetre = options.mmPerMetre;
    job.poses = engine::polypPosesNamed(display, options.poses);
    job.maps.clear();
    for (const std::string& name : options.maps) {
        const conformal::MapKind kind = conformal::mapKindFromName(name);
        if (std::find(job.maps.begin(), job.maps.end(), kind) == job.maps.end()) job.maps.push_back(kind);
    }
    if (std::find(job.maps.begin(), job.maps.end(), conformal::MapKind::Conformal) == job.maps.end()) {
        throw std::invalid_argument("--maps must include conformal: its prediction places the eyes and sets the targets");
    }
    job.angularRadiusDeg = options.angularRadiusDeg;
    job.minAngularRadiusDeg = std::min(job.minAngularRadiusDeg, options.angularRadiusDeg);
    job.warpMode = engine::warpModeFromName(options.warp);
    job.settings.gradient = engine::GradientFilter::Central;
    job.settings.lightHalfDistanceMm = 25.0;

    volumes::LoadOptions load;
    if (!options.rawSpec.empty()) load.raw = volumes::parseRawSpec(options.rawSpec);
    const volumes::LoadedVolume loaded = volumes::loadVolumeWithBricks(options.volumePath, load);
    job.toleranceMm = colon::polypToleranceMm(loaded.volume.spacingMm);
    engine::GpuContext context(engine::GpuContextOptions{false, options.device});
    engine::VolumeTexture texture(context, loaded.volume);
    engine::Raycaster raycaster(context, loaded.volume, texture, loaded.bricks);
    // Rank 0 bakes or finds the maps first; the others then load them from the cache it filled.
    std::map<conformal::MapKind, conformal::CubeMap> cubeMaps;
    const auto loadMaps = [&] {
        for (conformal::MapKind kind : job.maps) {
            if (kind == conformal::MapKind::None) continue;
            engine::Display withMap = display;
            withMap.map = kind;
            cubeMaps[kind] = engine::cubeMapFor(withMap, options.mapSize, "");
        }
    };
    distribution::rootFirst(mpi, loadMaps);

    // This rank's polyps: the r-th, the (r + N)-th, ... of those asked for.
    engine::PolypCheckJob mine = job;
    mine.polypIndices = distribution::dealt(job.polypIndices, mpi);
    std::optional<ProgressBar> progress;
    const auto onProgress = [&progress, &mpi](int done, int total) {
        if (!distribution::isReporter(mpi)) return;  // rank 0 shows its share
        if (!progress) progress.emplace(std::cerr, total, 0, isatty(fileno(stderr)) != 0);
        progress->update(done);
    };
    const engine::CubeMapLookup lookup = [&cubeMaps](conformal::MapKind kind) -> const conformal::CubeMap& {
        return cubeMaps.at(kind);
    };
    const engine::PolypCheckPlan plan = engine::planPolypCheck(job, lookup);
    const auto results = engine::checkPolyps(raycaster, mine, plan, lookup, onProgress);
    if (progress) progress->finish();
    // One file per polyp, pose and eye: each rank its own, once the check succeeded.
    fs::create_directories(crops);
    engine::writePolypCrops(results, crops, job.cropSize);

    // Rank 0 puts every rank's entries in the order one process gives them.
    const std::vector<std::string> all = distribution::gatherAtRoot(mpi, engine::polypResultEntries(results, plan).dump());
    if (!distribution::isReporter(mpi)) return;
    const nlohmann::json doc = engine::polypCheckDocument(nlohmann::json(engine::polypEntriesInOrder(all, job, plan)),
                                                          {options.volumePath, options.truthPath, options.warp}, job, plan);
    writeTextFile(jsonFile.string(), doc.dump(1) + "\n");
    if (!options.jsonPath.empty()) writeTextFile(options.jsonPath, doc.dump(1) + "\n");
    writeTextFile(tableFile.string(), engine::polypCheckMarkdown(doc["results"]));

    std::cout << "checked " << job.polypIndices.size() << " polyp(s) x " << plan.poses.size() << " poses x 3 eyes x "
              << job.maps.size() << " maps on " << context.driverDescription() << "; eyes where polyps subtend "
              << plan.angularRadiusDeg << " degrees\n";
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
    command->add_option("--truth", options->truthPath,
                        "Ground truth with polyps and a centreline (cvc phantom's JSON, or cvc insert-polyp's)")
        ->required();
    command->add_option("--polyps", options->polyps, "Polyps to check, by index in the truth (default: all)")
        ->delimiter(',');
    command->add_option("--poses", options->poses,
                        "Poses to check, by name (default: all of the display's; the names are in polyp_check.json)")
        ->delimiter(',');
    command->add_option("--maps", options->maps, "Maps to check: conformal (always), linear, none")
        ->delimiter(',')
        ->check(CLI::IsMember({"conformal", "linear", "none"}))
        ->capture_default_str();
    DisplayOptionFields display;
    display.display = &options->display;
    display.displayHelp = "Display preset or JSON file with a missing wall";
    display.wallSize = &options->wallSize;
    display.mapSize = &options->mapSize;
    display.mapSizeHelp = "Cube-map face size of the baked maps";
    display.warp = &options->warp;
    display.mmPerMetre = &options->mmPerMetre;
    addDisplayOptions(*command, display);
    command->add_option("--angular-radius", options->angularRadiusDeg,
                        "The polyp's angular radius from the eye in degrees, at most: the eye comes as close as the "
                        "map's predicted error at the targeted poses allows (down to 3 degrees)")
        ->check(CLI::Range(1.0, 30.0))
        ->capture_default_str();
    addOutputOptions(*command, options->outFolder, "Output folder", true, options->jsonPath,
                     "Also write the results' JSON to this file", options->force,
                     "Replace an earlier check in the output folder");
    addDeviceOption(*command, options->device);
    command->callback([options] { runPolypCheck(*options); });
}

}  // namespace app
