/// @brief `cvc coverage`: how much of the colon wall a fly-through shows the reader, per
/// display. The colon is found by the colon analysis, its wall meshed at the render's iso value
/// (colon/wall_surface.h), the fly-through rendered from the centre eye and every pixel's first
/// hit marked on the wall (colon/surface_coverage.h, engine/display/coverage_run.h). Writes the
/// percentage, the unseen patches largest first with a pose that shows each, pictures of them
/// and a review page; `--compare` runs the table of displays and maps on one path.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <sstream>

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "app/mpi_session.h"
#include "app/option_parsing.h"
#include "app/progress_bar.h"
#include "colon/colon_analysis.h"
#include "colon/coverage_image.h"
#include "colon/surface_coverage.h"
#include "colon/wall_surface.h"
#include "engine/core/gpu_context.h"
#include "engine/display/coverage_run.h"
#include "engine/display/display_json.h"
#include "engine/display/display_map.h"
#include "engine/display/patch_views.h"
#include "engine/display/review_page.h"
#include "engine/display/review_sheet.h"
#include "engine/output/png_writer.h"
#include "engine/render/volume_texture.h"
#include "volumes/brick_minmax.h"
#include "volumes/load_volume.h"

namespace app {
namespace {

namespace fs = std::filesystem;

enum class Directions { Antegrade, Retrograde, Both };

struct CoverageOptions {
    std::string volumePath;
    std::string rawSpec;
    std::string pathFile;
    std::string display = "ic5";
    std::string map;  // empty: the display's own
    bool isRetrograde = false;
    bool isBothDirections = false;
    double pathStepMm = 5.0;
    double smoothingMm = 8.0;
    int maxFrames = 0;
    std::string wallSize;  // empty: the display's own (with --compare: kCompareWallSize)
    double mmPerMetre = 10.0;
    int mapSize = 1024;
    std::string warp = "eye-centred";
    double isoHu = -500.0;
    colon::CoverageSettings coverage;
    double minPatchMm2 = 10.0;
    int patchPictures = 8;
    bool isCompare = false;
    std::string outFolder;
    std::string jsonPath;
    bool force = false;
    std::string device;
};

/// The reduced wall size of --compare: a quarter of the cabin's 1400-pixel walls across, so the
/// six rows run in minutes on a CPU; docs/coverage.md shows how full size changes a row.
constexpr const char* kCompareWallSize = "350x262";

/// One row of a run: a display, its map and the directions flown.
struct Row {
    std::string name;
    engine::Display display;
    Directions directions = Directions::Antegrade;
};

std::string directionsText(Directions d) {
    return d == Directions::Both ? "both" : d == Directions::Retrograde ? "retrograde" : "antegrade";
}

nlohmann::json vecJson(const glm::dvec3& v) { return {v.x, v.y, v.z}; }

/// What the analysis gives every row: the volume as rendered (cleansed where fluid was), the
/// colon's wall and the centreline.
struct Scene {
    volumes::LoadedVolume loaded;
    engine::Centreline centreline;
    colon::WallSurface wall;
};

Scene prepareScene(const CoverageOptions& options) {
    Scene scene;
    volumes::LoadOptions load;
    if (!options.rawSpec.empty()) load.raw = volumes::parseRawSpec(options.rawSpec);
    const bool isSpeaking = mpiSession().rank() == 0;  // one voice for the job under mpirun
    if (isSpeaking) std::cerr << "coverage: loading " << options.volumePath << '\n';
    scene.loaded = volumes::loadVolumeWithBricks(options.volumePath, load);
    const auto progress = [isSpeaking](const std::string& step, int done, int total) {
        if (isSpeaking) std::cerr << "coverage: colon [" << done << '/' << total << "] " << step << '\n';
    };
    const colon::ColonAnalysis analysis = colon::analyseColon(scene.loaded.volume, colon::ColonSettings{}, progress);
    // Cleansing rewrote the HU: the renderer must skip space by the volume it renders.
    if (analysis.isCleansed) scene.loaded.bricks = volumes::buildBrickMinMax(scene.loaded.volume);

    if (options.pathFile == "auto") {
        for (const auto& segment : analysis.segments) scene.centreline.segments.push_back(segment.centreline.pointsMm);
        scene.centreline.anterior = analysis.anteriorMm;
    } else {
        scene.centreline = engine::readCentreline(options.pathFile);
    }
    if (isSpeaking) std::cerr << "coverage: meshing the colon wall at " << options.isoHu << " HU\n";
    std::vector<uint8_t> isLumen(analysis.labels.hu.size());
    for (std::size_t n = 0; n < isLumen.size(); ++n) isLumen[n] = analysis.labels.hu[n] >= colon::kLabelFirstSegment ? 1 : 0;
    colon::WallSurfaceSettings wallSettings;
    wallSettings.isoHu = options.isoHu;
    scene.wall = colon::colonWallSurface(scene.loaded.volume, isLumen, wallSettings);
    if (isSpeaking) std::cerr << "coverage: colon wall " << std::fixed << std::setprecision(0) << scene.wall.totalAreaMm2 << " mm^2 in "
              << scene.wall.size() << " elements\n";
    return scene;
}

std::vector<engine::CameraPose> posesOf(const CoverageOptions& options, const engine::Centreline& centreline,
                                        Directions directions) {
    engine::PathSettings path;
    path.stepMm = options.pathStepMm;
    path.smoothingMm = options.smoothingMm;
    if (centreline.anterior) path.initialUp = *centreline.anterior;
    std::vector<engine::CameraPose> poses;
    for (engine::Direction d : {engine::Direction::Antegrade, engine::Direction::Retrograde}) {
        if ((d == engine::Direction::Antegrade && directions == Directions::Retrograde) ||
            (d == engine::Direction::Retrograde && directions == Directions::Antegrade)) {
            continue;
        }
        path.direction = d;
        std::vector<engine::CameraPose> more = engine::posesAlongSegments(centreline, path);
        if (options.maxFrames > 0 && static_cast<int>(more.size()) > options.maxFrames) more.resize(static_cast<std::size_t>(options.maxFrames));
        poses.insert(poses.end(), more.begin(), more.end());
    }
    return poses;
}

std::string rowDescription(const colon::CoverageSettings& s) {
    std::ostringstream text;
    text << "A wall element counts as seen when a pixel's first hit lands on it with at most " << s.maxFootprintMm2
         << " mm\u00b2 of wall per pixel and at most " << s.maxViewAngleDeg
         << "\u00b0 between its normal and the direction to the eye (centre eye, mono). The wall is the iso-surface "
            "bounding the colon lumen that the colon analysis found.";
    return text.str();
}

/// What one row measured.
struct RowResult {
    engine::CoverageJob job;          // every frame of the row
    engine::CoverageRunSummary run;   // this rank's frames
    std::vector<double> cumulativePercent;  // per frame of the row, in order (every rank's frames)
    double sheetSeconds = 0.0;
    std::vector<colon::UnseenPatch> patches;  // every unseen patch of the minimum area, largest first
    std::vector<engine::PatchView> located;         // the largest, with a pose and a picture
};

engine::CoverageJob coverageJobOf(const CoverageOptions& options, const Row& row, const Scene& scene) {
    engine::CoverageJob job;
    job.display = row.display;
    job.poses = posesOf(options, scene.centreline, row.directions);
    job.mmPerMetre = options.mmPerMetre;
    job.settings.isoHu = options.isoHu;
    job.settings.stepVoxels = 1.0;  // as display renders: hits refined by bisection
    job.settings.gradient = engine::GradientFilter::Central;
    job.settings.lightHalfDistanceMm = 25.0;
    job.warpMode = engine::warpModeFromName(options.warp);
    return job;
}

/// Flies this rank's frames of the row's path (every frame for one process; frame i goes to rank
/// i mod N under mpirun), marks what they show and writes each one's sheet.
RowResult flyAndMeasure(const CoverageOptions& options, const Row& row, const Scene& scene, engine::Raycaster& raycaster,
                        colon::SurfaceCoverage& coverage, const fs::path& folder) {
    MpiSession& mpi = mpiSession();
    RowResult result;
    result.job = coverageJobOf(options, row, scene);
    // Rank 0 bakes or finds the map first; the others then load it from the cache it filled.
    const auto loadMap = [&] {
        const conformal::CubeMap map = engine::cubeMapFor(row.display, options.mapSize, "");
        raycaster.setCubeMap(map.size, map.rgba);
    };
    const bool hasMap = row.display.map != conformal::MapKind::None;
    if (hasMap && mpi.rank() == 0) loadMap();
    mpi.barrier();
    if (hasMap && mpi.rank() != 0) loadMap();

    engine::CoverageJob mine = result.job;
    mine.poses.clear();
    std::vector<int> frameOf;  // the row's frame index of each of mine
    for (std::size_t i = 0; i < result.job.poses.size(); ++i) {
        if (static_cast<int>(i % static_cast<std::size_t>(mpi.ranks())) != mpi.rank()) continue;
        mine.poses.push_back(result.job.poses[i]);
        frameOf.push_back(static_cast<int>(i));
    }
    const int total = static_cast<int>(result.job.poses.size());
    if (mpi.rank() == 0) std::cerr << "coverage: " << row.name << ": " << total << " frame(s)\n";
    std::optional<ProgressBar> progress;
    engine::CoverageHooks hooks;
    // Rank 0 shows the whole row: the frames whose sheets are in the folder, whoever wrote them.
    hooks.onProgress = [&](int, int) {
        if (mpi.rank() != 0) return;
        int done = 0;
        for (int i = 0; i < total; ++i) done += fs::exists(folder / engine::frameFolderName(i) / "sheet.png") ? 1 : 0;
        if (!progress) progress.emplace(std::cerr, total, done, isatty(fileno(stderr)) != 0);
        progress->update(done);
    };
    hooks.onFrame = [&](int index, const std::vector<engine::WallImage>& walls) {
        const auto start = std::chrono::steady_clock::now();
        std::map<engine::WallName, engine::RgbaImage> byWall;
        for (const auto& w : walls) byWall[w.wall] = engine::RgbaImage{w.image.width, w.image.height, w.image.rgba};
        const engine::RgbaImage sheet = engine::crossLayout(result.job.display, byWall);
        const fs::path frameFolder = folder / engine::frameFolderName(frameOf[static_cast<std::size_t>(index)]);
        fs::create_directories(frameFolder);
        engine::writePng((frameFolder / "sheet.png").string(), sheet.width, sheet.height, sheet.rgba, true,
                         engine::kFastPngEncoding);
        result.sheetSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    };
    try {
        result.run = engine::runCoverage(raycaster, mine, coverage, hooks);
    } catch (...) {
        if (progress) progress->finish();
        throw;
    }
    // What each frame showed first, by the row's frame index, for rank 0 to merge.
    nlohmann::json shown = nlohmann::json::array();
    for (std::size_t f = 0; f < result.run.frames.size(); ++f) shown.push_back({frameOf[f], result.run.frames[f].newlySeenElements});
    const std::vector<std::string> all = mpi.gather(shown.dump());
    mpi.barrier();
    if (progress) {
        hooks.onProgress(total, total);
        progress->finish();
    }
    if (mpi.rank() != 0) return result;
    // Replayed in frame order, the frames' first sightings give the whole row's coverage and
    // its curve, the same as one process flying every frame (seen is an OR over views).
    std::vector<std::vector<uint32_t>> byFrame(result.job.poses.size());
    for (const std::string& text : all) {
        for (const auto& entry : nlohmann::json::parse(text)) {
            byFrame.at(entry[0].get<std::size_t>()) = entry[1].get<std::vector<uint32_t>>();
        }
    }
    colon::SurfaceCoverage merged(coverage.surface(), options.coverage);
    for (const auto& elements : byFrame) {
        merged.markSeen(elements);
        result.cumulativePercent.push_back(merged.percent());
    }
    coverage = std::move(merged);
    return result;
}

/// The unseen patches, a pose for each of the largest, and their pictures in folder/patches/.
void locateAndPicture(const CoverageOptions& options, const Scene& scene, engine::Raycaster& raycaster,
                      const colon::SurfaceCoverage& coverage, RowResult& result, const fs::path& folder) {
    const glm::dvec3 spacing = scene.loaded.volume.spacingMm;
    const double snapMm = 1.5 * std::max({spacing.x, spacing.y, spacing.z});
    result.patches = coverage.unseenPatches(options.minPatchMm2);
    result.located = engine::locatePatches(raycaster, coverage, result.patches, result.job.poses, scene.loaded.volume,
                                           result.job.settings, snapMm, options.patchPictures);
    fs::create_directories(folder / "patches");
    for (std::size_t p = 0; p < result.located.size(); ++p) {
        engine::PatchView& r = result.located[p];
        std::ostringstream name;
        name << "patches/patch_" << std::setw(2) << std::setfill('0') << p + 1 << ".png";
        r.picture = name.str();
        const engine::RgbaImage picture =
            engine::tintedUnseen(engine::patchView(raycaster, r.pose, r.patch.centreMm, result.job.settings, 320),
                                 coverage, snapMm);
        engine::writePng((folder / r.picture).string(), picture.width, picture.height, picture.rgba, true);
    }
    std::vector<colon::UnseenPatch> ringed;
    for (const auto& r : result.located) ringed.push_back(r.patch);
    const engine::RgbaImage overview = colon::coverageImage(scene.loaded.volume, coverage, ringed);
    engine::writePng((folder / "coverage.png").string(), overview.width, overview.height, overview.rgba, true);
}

nlohmann::json rowJson(const CoverageOptions& options, const Row& row, const colon::SurfaceCoverage& coverage,
                       const RowResult& result, const std::string& rendererDescription) {
    nlohmann::json doc;
    doc["display"] = row.display.name;
    doc["map"] = conformal::mapKindName(row.display.map);
    doc["directions"] = directionsText(row.directions);
    doc["walls"] = nlohmann::json::array();
    for (const auto& wall : row.display.walls) {
        doc["walls"].push_back({{"name", engine::wallNameText(wall.name)}, {"width", wall.width}, {"height", wall.height}});
    }
    doc["frames"] = result.job.poses.size();
    doc["path_step_mm"] = options.pathStepMm;
    doc["coverage_percent"] = coverage.percent();
    doc["seen_mm2"] = coverage.seenAreaMm2();
    doc["wall_mm2"] = coverage.wallAreaMm2();
    doc["thresholds"] = {{"max_footprint_mm2", options.coverage.maxFootprintMm2},
                         {"max_view_angle_deg", options.coverage.maxViewAngleDeg},
                         {"min_patch_mm2", options.minPatchMm2}};
    doc["unseen_patches"] = result.patches.size();
    doc["patches"] = nlohmann::json::array();
    for (std::size_t p = 0; p < result.patches.size(); ++p) {
        const colon::UnseenPatch& patch = result.patches[p];
        nlohmann::json entry = {{"area_mm2", patch.areaMm2}, {"centre_mm", vecJson(patch.centreMm)},
                                {"normal", vecJson(patch.normal)}};
        if (p < result.located.size()) {
            const engine::PatchView& r = result.located[p];
            entry["pose"] = {{"position", vecJson(r.pose.positionMm)}, {"look_at", vecJson(r.patch.centreMm)},
                             {"up", vecJson(r.pose.up)}};
            entry["nearest_frame"] = r.nearestFrame;
            entry["shown_by_pose_percent"] = r.shownPercent;
            entry["picture"] = r.picture;
        }
        doc["patches"].push_back(entry);
    }
    nlohmann::json perFrame = nlohmann::json::array();
    for (double percent : result.cumulativePercent) perFrame.push_back(percent);
    doc["cumulative_percent"] = perFrame;
    doc["timing"] = {{"seconds", result.run.seconds},
                     {"measure_seconds", result.run.measureSeconds},
                     {"sheet_seconds", result.sheetSeconds},
                     {"ray_casting_ms", result.run.rayCastingMs}};
    doc["ranks"] = mpiSession().ranks();
    doc["renderer"] = rendererDescription;
    return doc;
}

void writeRowPage(const CoverageOptions& options, const Row& row, const Scene& scene,
                  const colon::SurfaceCoverage& coverage, const RowResult& result,
                  const std::string& rendererDescription, const fs::path& folder) {
    engine::ReviewPage page;
    page.title = "Coverage: " + row.name;
    page.facts = {{"volume", fs::absolute(options.volumePath).string()},
                  {"display", row.display.name},
                  {"map", conformal::mapKindName(row.display.map)},
                  {"directions", directionsText(row.directions)},
                  {"renderer", rendererDescription}};
    page.ct = &scene.loaded.volume;
    page.sheetCaption = "the centre eye's walls, unfolded as a cross (floor below the front wall), as coverage saw them";
    for (std::size_t i = 0; i < result.job.poses.size(); ++i) {
        engine::ReviewFrame frame;
        frame.index = static_cast<int>(i);
        frame.pose = result.job.poses[i];
        frame.sheet = engine::frameFolderName(frame.index) + "/sheet.png";
        frame.images.push_back({"centre eye", frame.sheet, ""});
        page.frames.push_back(frame);
    }
    engine::ReviewCoverage review;
    review.percent = coverage.percent();
    review.seenMm2 = coverage.seenAreaMm2();
    review.wallMm2 = coverage.wallAreaMm2();
    review.overview = "coverage.png";
    review.description = rowDescription(options.coverage);
    review.cumulativePercent = result.cumulativePercent;
    for (std::size_t p = 0; p < result.located.size(); ++p) {
        const engine::PatchView& r = result.located[p];
        review.patches.push_back({static_cast<int>(p) + 1, r.patch.areaMm2, r.patch.centreMm, r.pose, r.nearestFrame, r.picture});
    }
    page.coverage = review;
    page.measurements = {{"frames", std::to_string(result.job.poses.size())},
                         {"unseen patches of " + std::to_string(static_cast<int>(options.minPatchMm2)) + " mm\u00b2 and more",
                          std::to_string(result.patches.size())}};
    engine::writeReviewPage(folder.string(), page);
}

/// Renders one row, measures its coverage and writes its folder; returns its JSON summary.
nlohmann::json runRow(const CoverageOptions& options, const Row& row, Scene& scene, engine::Raycaster& raycaster,
                      const std::string& rendererDescription, const fs::path& folder) {
    engine::validateDisplay(row.display);
    MpiSession& mpi = mpiSession();
    if (mpi.rank() == 0) fs::create_directories(folder);
    mpi.barrier();
    colon::SurfaceCoverage coverage(scene.wall, options.coverage);
    RowResult result = flyAndMeasure(options, row, scene, raycaster, coverage, folder);
    if (mpi.rank() != 0) return {};  // rank 0 has every rank's frames: it reports the row
    locateAndPicture(options, scene, raycaster, coverage, result, folder);
    const nlohmann::json doc = rowJson(options, row, coverage, result, rendererDescription);
    writeTextFile((folder / "coverage.json").string(), doc.dump(1) + "\n");
    writeRowPage(options, row, scene, coverage, result, rendererDescription, folder);
    std::cout << std::fixed << std::setprecision(1) << row.name << ": " << coverage.percent() << " % of "
              << coverage.wallAreaMm2() / 100.0 << " cm^2 seen over " << result.job.poses.size() << " frames, "
              << result.patches.size() << " unseen patch(es) of " << options.minPatchMm2 << " mm^2 or more; "
              << std::setprecision(2) << result.run.seconds << " s (measuring " << result.run.measureSeconds << " s)\n";
    return doc;
}

engine::Display rowDisplay(const std::string& name, const std::string& map, const std::string& wallSize) {
    engine::Display display = engine::loadDisplay(name);
    if (!map.empty()) display.map = conformal::mapKindFromName(map);
    if (!wallSize.empty()) resizeWalls(display, wallSize);
    engine::validateDisplay(display);
    return display;
}

/// Names this command writes into its folder, and nothing else: --force replaces these only.
bool isOurEntry(const std::string& name) {
    static const std::vector<std::string> kNames = {"coverage.json", "coverage.png", "patches", "compare.json",
                                                    "compare.md"};
    if (std::find(kNames.begin(), kNames.end(), name) != kNames.end()) return true;
    if (name.rfind("frame_", 0) == 0 || name.rfind("row_", 0) == 0) return true;
    const auto page = engine::reviewPageFileNames();
    return std::find(page.begin(), page.end(), name) != page.end();
}

void prepareFolder(const CoverageOptions& options) {
    const fs::path folder(options.outFolder);
    if (fs::exists(folder) && !fs::is_directory(folder)) throw std::runtime_error(options.outFolder + ": exists and is not a folder");
    if (fs::exists(folder) && !fs::is_empty(folder)) {
        if (!options.force) throw std::runtime_error(options.outFolder + ": exists and is not empty (pass --force to replace it)");
        for (const auto& entry : fs::directory_iterator(folder)) {
            if (isOurEntry(entry.path().filename().string())) fs::remove_all(entry.path());
        }
    }
    fs::create_directories(folder);
    if (access(folder.c_str(), W_OK) != 0) throw std::runtime_error(options.outFolder + ": folder is not writable");
}

std::vector<Row> rowsOf(const CoverageOptions& options) {
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
    if (options.pathFile.empty()) throw std::invalid_argument("--path is required (a centreline file, or auto)");
    if (options.isRetrograde && options.isBothDirections) {
        throw std::invalid_argument("--retrograde and --both-directions exclude each other");
    }
    if (!(options.pathStepMm >= 0.1 && options.pathStepMm <= 100.0)) throw std::invalid_argument("--path-step must be 0.1..100 mm");
    if (!(options.smoothingMm >= 0.0 && options.smoothingMm <= 200.0)) throw std::invalid_argument("--smoothing must be 0..200 mm");
    if (options.maxFrames < 0) throw std::invalid_argument("--frames must not be negative");
    if (!(options.mmPerMetre > 0.0 && options.mmPerMetre <= 1000.0)) throw std::invalid_argument("--scale must be in (0, 1000] mm per metre");
    if (options.mapSize < 16 || options.mapSize > 4096) throw std::invalid_argument("--map-size must be 16..4096");
    if (!std::isfinite(options.isoHu)) throw std::invalid_argument("--iso must be a finite HU value");
    if (!(options.coverage.maxFootprintMm2 > 0.0 && options.coverage.maxFootprintMm2 <= 100.0)) {
        throw std::invalid_argument("--max-footprint must be in (0, 100] mm^2 per pixel");
    }
    if (!(options.coverage.maxViewAngleDeg > 0.0 && options.coverage.maxViewAngleDeg <= 90.0)) {
        throw std::invalid_argument("--max-angle must be in (0, 90] degrees");
    }
    if (!(options.minPatchMm2 >= 0.0 && std::isfinite(options.minPatchMm2))) throw std::invalid_argument("--min-patch must be >= 0 mm^2");
    if (options.patchPictures < 0 || options.patchPictures > 100) throw std::invalid_argument("--patch-pictures must be 0..100");
}

void runCoverageCommand(const CoverageOptions& options) {
    // Under mpirun every rank analyses the same volume (the same wall, element for element) and
    // flies its share of each row's frames; rank 0 prepares the folder, merges and reports.
    MpiSession& mpi = mpiSession();
    validate(options);
    const std::vector<Row> rows = rowsOf(options);  // a bad display fails before anything loads
    if (mpi.rank() == 0) {
        prepareFolder(options);
        if (!options.jsonPath.empty()) requireWritableOutput(options.jsonPath, options.force);
    }
    mpi.barrier();

    Scene scene = prepareScene(options);
    engine::GpuContext context(engine::GpuContextOptions{false, options.device});
    engine::VolumeTexture texture(context, scene.loaded.volume);
    engine::Raycaster raycaster(context, scene.loaded.volume, texture, scene.loaded.bricks);

    const fs::path folder(options.outFolder);
    nlohmann::json summary;
    if (!options.isCompare) {
        summary = runRow(options, rows.front(), scene, raycaster, context.driverDescription(), folder);
    } else if (mpi.rank() != 0) {
        for (const Row& row : rows) runRow(options, row, scene, raycaster, context.driverDescription(), folder / row.name);
    } else {
        summary["wall_size"] = options.wallSize.empty() ? kCompareWallSize : options.wallSize;
        summary["path_step_mm"] = options.pathStepMm;
        summary["volume"] = fs::absolute(options.volumePath).string();
        summary["rows"] = nlohmann::json::array();
        std::ostringstream table;
        table << "| row | display | map | directions | frames | coverage | unseen patches |\n|---|---|---|---|---:|---:|---:|\n";
        for (const Row& row : rows) {
            const nlohmann::json result = runRow(options, row, scene, raycaster, context.driverDescription(), folder / row.name);
            summary["rows"].push_back({{"row", row.name},
                                       {"display", result["display"]},
                                       {"map", result["map"]},
                                       {"directions", result["directions"]},
                                       {"frames", result["frames"]},
                                       {"coverage_percent", result["coverage_percent"]},
                                       {"seen_mm2", result["seen_mm2"]},
                                       {"wall_mm2", result["wall_mm2"]},
                                       {"unseen_patches", result["unseen_patches"]},
                                       {"seconds", result["timing"]["seconds"]}});
            table << "| " << row.name << " | " << result["display"].get<std::string>() << " | "
                  << result["map"].get<std::string>() << " | " << result["directions"].get<std::string>() << " | "
                  << result["frames"] << " | " << std::fixed << std::setprecision(1)
                  << result["coverage_percent"].get<double>() << " % | " << result["unseen_patches"] << " |\n";
        }
        writeTextFile((folder / "compare.json").string(), summary.dump(1) + "\n");
        writeTextFile((folder / "compare.md").string(), table.str());
        std::cout << table.str();
    }
    if (mpi.rank() != 0) return;
    if (!options.jsonPath.empty()) writeTextFile(options.jsonPath, summary.dump(1) + "\n");
    std::cout << "wrote " << options.outFolder << '\n';
}

}  // namespace

void addCoverageCommand(CLI::App& program) {
    auto options = std::make_shared<CoverageOptions>();
    CLI::App* command = program.add_subcommand(
        "coverage", "Measure how much of the colon wall a fly-through shows on a display, and where the unseen "
                    "patches are; --compare runs the table of displays and maps");
    command->add_option("volume,--volume", options->volumePath,
                        "Volume: DICOM folder, .nrrd/.nhdr, .nii/.nii.gz, .mha/.mhd, .vdb, or raw with --raw")
        ->required();
    command->add_option("--raw", options->rawSpec, "Describe a headerless raw file, e.g. 512x512x451:int16:0.7x0.7x1.25");
    command->add_option("--path", options->pathFile,
                        "Centreline: a phantom's JSON ground truth, cvc colon's colon.json, a text file of x y z, or "
                        "auto (the colon analysis's own)")->required();
    command->add_option("--display", options->display, "ic5, ic6, cave6, forward or a display JSON file")->capture_default_str();
    command->add_option("--map", options->map, "Override the display's map: conformal, linear, none")
        ->check(CLI::IsMember({"conformal", "linear", "none"}));
    command->add_flag("--retrograde", options->isRetrograde, "Fly caecum -> rectum (default: antegrade)");
    command->add_flag("--both-directions", options->isBothDirections, "Fly antegrade, then retrograde");
    command->add_option("--path-step", options->pathStepMm, "Arc length between frames in mm")->capture_default_str();
    command->add_option("--smoothing", options->smoothingMm, "Half-width in mm of the view-direction smoothing")
        ->capture_default_str();
    command->add_option("--frames", options->maxFrames, "At most this many frames per direction");
    command->add_option("--wall-size", options->wallSize,
                        std::string("Walls resized to WxH across the box's width at one pixel density (default: the "
                                    "display's own; with --compare ") + kCompareWallSize + ")");
    command->add_option("--scale", options->mmPerMetre, "Volume millimetres per CAVE metre")->capture_default_str();
    command->add_option("--map-size", options->mapSize, "Cube-map texels per face edge")->capture_default_str();
    command->add_option("--warp", options->warp, "eye-centred, polyline, chord or exact (the centre eye's rays: all but exact are one chord)")
        ->check(CLI::IsMember(engine::bendingWarpModeNames()))
        ->capture_default_str();
    command->add_option("--iso", options->isoHu, "Iso value in HU of the wall (rendered and meshed)")->capture_default_str();
    command->add_option("--max-footprint", options->coverage.maxFootprintMm2,
                        "Largest wall area per pixel, mm^2, for a pixel to count")->capture_default_str();
    command->add_option("--max-angle", options->coverage.maxViewAngleDeg,
                        "Largest angle between the wall's normal and the view, degrees")->capture_default_str();
    command->add_option("--min-patch", options->minPatchMm2, "Smallest unseen patch reported, mm^2")->capture_default_str();
    command->add_option("--patch-pictures", options->patchPictures, "Pictures (and poses) for this many largest patches")
        ->capture_default_str();
    command->add_flag("--compare", options->isCompare,
                      "Run the table: forward antegrade, forward both directions, ic5 without a map, linear and "
                      "conformal, ic6; one subfolder per row");
    command->add_option("-o,--out", options->outFolder, "Output folder")->required();
    command->add_option("--json", options->jsonPath, "Also write the summary JSON to this file");
    command->add_flag("--force", options->force, "Replace an earlier coverage run in the output folder");
    command->add_option("--device", options->device,
                        "Vulkan device: index, part of its name, 'cpu' or 'gpu' (default: $CVC_DEVICE, else the best)");
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
