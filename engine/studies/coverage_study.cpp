#include "engine/studies/coverage_study.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <map>
#include <sstream>
#include <stdexcept>

#include <unistd.h>

#include "colon/colon_analysis.h"
#include "colon/coverage_image.h"
#include "engine/display/display_json.h"
#include "engine/output/png_writer.h"
#include "engine/review/review_page.h"
#include "engine/review/review_sheet.h"
#include "volumes/brick_minmax.h"

namespace engine {
namespace {

namespace fs = std::filesystem;

nlohmann::json vecJson(const glm::dvec3& v) { return {v.x, v.y, v.z}; }

std::vector<CameraPose> posesOf(const CoverageStudySettings& settings, const Centreline& centreline,
                                CoverageDirections directions) {
    PathSettings path;
    path.stepMm = settings.pathStepMm;
    path.smoothingMm = settings.smoothingMm;
    if (centreline.anterior) path.initialUp = *centreline.anterior;
    std::vector<CameraPose> poses;
    for (Direction d : {Direction::Antegrade, Direction::Retrograde}) {
        if ((d == Direction::Antegrade && directions == CoverageDirections::Retrograde) ||
            (d == Direction::Retrograde && directions == CoverageDirections::Antegrade)) {
            continue;
        }
        path.direction = d;
        std::vector<CameraPose> more = posesAlongSegments(centreline, path);
        if (settings.maxFrames > 0 && static_cast<int>(more.size()) > settings.maxFrames) more.resize(static_cast<std::size_t>(settings.maxFrames));
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

/// The names a coverage run writes into its folder, and nothing else: --force replaces these only.
bool isOurEntry(const std::string& name) {
    static const std::vector<std::string> kNames = {"coverage.json", "coverage.png", "patches", "compare.json",
                                                    "compare.md", "unseen_patches.mrk.json"};
    if (std::find(kNames.begin(), kNames.end(), name) != kNames.end()) return true;
    if (name.rfind("frame_", 0) == 0 || name.rfind("row_", 0) == 0) return true;
    const auto page = reviewPageFileNames();
    return std::find(page.begin(), page.end(), name) != page.end();
}

}  // namespace

void prepareCoverageFolder(const std::string& outFolder, bool force) {
    const fs::path folder(outFolder);
    if (fs::exists(folder) && !fs::is_directory(folder)) throw std::runtime_error(outFolder + ": exists and is not a folder");
    if (fs::exists(folder) && !fs::is_empty(folder)) {
        if (!force) throw std::runtime_error(outFolder + ": exists and is not empty (pass --force to replace it)");
        for (const auto& entry : fs::directory_iterator(folder)) {
            if (isOurEntry(entry.path().filename().string())) fs::remove_all(entry.path());
        }
    }
    fs::create_directories(folder);
    if (access(folder.c_str(), W_OK) != 0) throw std::runtime_error(outFolder + ": folder is not writable");
}

std::string coverageDirectionsText(CoverageDirections d) {
    return d == CoverageDirections::Both ? "both" : d == CoverageDirections::Retrograde ? "retrograde" : "antegrade";
}

void validateCoverageStudySettings(const CoverageStudySettings& s, int mapSize) {
    if (s.pathFile.empty()) throw std::invalid_argument("--path is required (a centreline file, or auto)");
    if (!(s.pathStepMm >= 0.1 && s.pathStepMm <= 100.0)) throw std::invalid_argument("--path-step must be 0.1..100 mm");
    if (!(s.smoothingMm >= 0.0 && s.smoothingMm <= 200.0)) throw std::invalid_argument("--smoothing must be 0..200 mm");
    if (s.maxFrames < 0) throw std::invalid_argument("--frames must not be negative");
    if (!(s.mmPerMetre > 0.0 && s.mmPerMetre <= 1000.0)) throw std::invalid_argument("--scale must be in (0, 1000] mm per metre");
    if (mapSize < 16 || mapSize > 4096) throw std::invalid_argument("--map-size must be 16..4096");
    if (!std::isfinite(s.isoHu)) throw std::invalid_argument("--iso must be a finite HU value");
    if (!(s.coverage.maxFootprintMm2 > 0.0 && s.coverage.maxFootprintMm2 <= 100.0)) {
        throw std::invalid_argument("--max-footprint must be in (0, 100] mm^2 per pixel");
    }
    if (!(s.coverage.maxViewAngleDeg > 0.0 && s.coverage.maxViewAngleDeg <= 90.0)) {
        throw std::invalid_argument("--max-angle must be in (0, 90] degrees");
    }
    if (!(s.minPatchMm2 >= 0.0 && std::isfinite(s.minPatchMm2))) throw std::invalid_argument("--min-patch must be >= 0 mm^2");
    if (s.patchPictures < 0 || s.patchPictures > 100) throw std::invalid_argument("--patch-pictures must be 0..100");
}

Display coverageRowDisplay(const std::string& name, const std::string& map, int wallWidth) {
    Display display = loadDisplay(name);
    if (!map.empty()) display.map = conformal::mapKindFromName(map);
    if (wallWidth > 0) resizeWallsToWidth(display, wallWidth);
    validateDisplay(display);
    return display;
}

CoverageScene prepareCoverageScene(const CoverageStudySettings& settings,
                                   const std::function<void(const std::string&)>& say) {
    volumes::LoadOptions load;
    if (!settings.rawSpec.empty()) load.raw = volumes::parseRawSpec(settings.rawSpec);
    say("coverage: loading " + settings.volumePath);
    return coverageSceneOf(volumes::loadVolumeWithBricks(settings.volumePath, load), settings, say);
}

CoverageScene coverageSceneOf(volumes::LoadedVolume loaded, const CoverageStudySettings& settings,
                              const std::function<void(const std::string&)>& say) {
    CoverageScene scene;
    scene.loaded = std::move(loaded);
    const auto progress = [&say](const std::string& step, int done, int total) {
        say("coverage: colon [" + std::to_string(done) + '/' + std::to_string(total) + "] " + step);
    };
    const colon::ColonAnalysis analysis = colon::analyseColon(scene.loaded.volume, colon::ColonSettings{}, progress);
    // Cleansing rewrote the HU: the renderer must skip space by the volume it renders.
    if (analysis.isCleansed) scene.loaded.bricks = volumes::buildBrickMinMax(scene.loaded.volume);

    if (settings.pathFile == "auto") {
        for (const auto& segment : analysis.segments) scene.centreline.segments.push_back(segment.centreline.pointsMm);
        scene.centreline.anterior = analysis.anteriorMm;
    } else {
        scene.centreline = readCentreline(settings.pathFile);
    }
    std::ostringstream meshing;
    meshing << "coverage: meshing the colon wall at " << settings.isoHu << " HU";
    say(meshing.str());
    std::vector<uint8_t> isLumen(analysis.labels.hu.size());
    for (std::size_t n = 0; n < isLumen.size(); ++n) isLumen[n] = analysis.labels.hu[n] >= colon::kLabelFirstSegment ? 1 : 0;
    colon::WallSurfaceSettings wallSettings;
    wallSettings.isoHu = settings.isoHu;
    scene.wall = colon::colonWallSurface(scene.loaded.volume, isLumen, wallSettings);
    std::ostringstream wall;
    wall << "coverage: colon wall " << std::fixed << std::setprecision(0) << scene.wall.totalAreaMm2 << " mm^2 in "
         << scene.wall.size() << " elements";
    say(wall.str());
    return scene;
}

CoverageJob coverageJobOf(const CoverageStudySettings& settings, const CoverageRow& row, const CoverageScene& scene) {
    CoverageJob job;
    job.display = row.display;
    job.poses = posesOf(settings, scene.centreline, row.directions);
    job.mmPerMetre = settings.mmPerMetre;
    job.settings = defaultRenderSettings(RenderUse::DisplayFrames);  // as display renders
    job.settings.isoHu = settings.isoHu;
    job.warpMode = settings.warpMode;
    return job;
}

void writeCoverageSheet(const fs::path& folder, int frameIndex, const Display& display, const std::vector<WallImage>& walls) {
    std::map<WallName, RgbaImage> byWall;
    for (const auto& w : walls) byWall[w.wall] = RgbaImage{w.image.width, w.image.height, w.image.rgba};
    const RgbaImage sheet = crossLayout(display, byWall);
    const fs::path frameFolder = folder / frameFolderName(frameIndex);
    fs::create_directories(frameFolder);
    writePng((frameFolder / "sheet.png").string(), sheet.width, sheet.height, sheet.rgba, true, kFastPngEncoding);
}

colon::SurfaceCoverage mergedCoverage(const colon::WallSurface& surface, const colon::CoverageSettings& settings,
                                      const std::vector<std::vector<uint32_t>>& firstSightingsByFrame,
                                      std::vector<double>& cumulativePercent) {
    colon::SurfaceCoverage merged(surface, settings);
    for (const auto& elements : firstSightingsByFrame) {
        merged.markSeen(elements);
        cumulativePercent.push_back(merged.percent());
    }
    return merged;
}

void locateAndPictureUnseen(const CoverageStudySettings& settings, const CoverageScene& scene, Raycaster& raycaster,
                            const colon::SurfaceCoverage& coverage, CoverageRowResult& result, const fs::path& folder) {
    const glm::dvec3 spacing = scene.loaded.volume.spacingMm;
    const double snapMm = 1.5 * std::max({spacing.x, spacing.y, spacing.z});
    result.patches = coverage.unseenPatches(settings.minPatchMm2);
    result.located = locatePatches(raycaster, coverage, result.patches, result.job.poses, scene.loaded.volume,
                                           result.job.settings, snapMm, settings.patchPictures);
    fs::create_directories(folder / "patches");
    for (std::size_t p = 0; p < result.located.size(); ++p) {
        PatchView& r = result.located[p];
        std::ostringstream name;
        name << "patches/patch_" << std::setw(2) << std::setfill('0') << p + 1 << ".png";
        r.picture = name.str();
        const RgbaImage picture =
            tintedUnseen(patchView(raycaster, r.pose, r.patch.centreMm, result.job.settings, 320),
                                 coverage, snapMm);
        writePng((folder / r.picture).string(), picture.width, picture.height, picture.rgba, true);
    }
    std::vector<colon::UnseenPatch> ringed;
    for (const auto& r : result.located) ringed.push_back(r.patch);
    const RgbaImage overview = colon::coverageImage(scene.loaded.volume, coverage, ringed);
    writePng((folder / "coverage.png").string(), overview.width, overview.height, overview.rgba, true);
}

nlohmann::json coverageRowJson(const CoverageStudySettings& settings, const CoverageRow& row,
                               const colon::SurfaceCoverage& coverage, const CoverageRowResult& result,
                               const std::string& rendererDescription, int ranks) {
    nlohmann::json doc;
    doc["display"] = row.display.name;
    doc["map"] = conformal::mapKindName(row.display.map);
    doc["directions"] = coverageDirectionsText(row.directions);
    doc["walls"] = nlohmann::json::array();
    for (const auto& wall : row.display.walls) {
        doc["walls"].push_back({{"name", wallNameText(wall.name)}, {"width", wall.width}, {"height", wall.height}});
    }
    doc["frames"] = result.job.poses.size();
    doc["path_step_mm"] = settings.pathStepMm;
    doc["coverage_percent"] = coverage.percent();
    doc["seen_mm2"] = coverage.seenAreaMm2();
    doc["wall_mm2"] = coverage.wallAreaMm2();
    doc["thresholds"] = {{"max_footprint_mm2", settings.coverage.maxFootprintMm2},
                         {"max_view_angle_deg", settings.coverage.maxViewAngleDeg},
                         {"min_patch_mm2", settings.minPatchMm2}};
    doc["unseen_patches"] = result.patches.size();
    doc["patches"] = nlohmann::json::array();
    for (std::size_t p = 0; p < result.patches.size(); ++p) {
        const colon::UnseenPatch& patch = result.patches[p];
        nlohmann::json entry = {{"area_mm2", patch.areaMm2}, {"centre_mm", vecJson(patch.centreMm)},
                                {"normal", vecJson(patch.normal)}};
        if (p < result.located.size()) {
            const PatchView& r = result.located[p];
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
    doc["ranks"] = ranks;
    doc["renderer"] = rendererDescription;
    return doc;
}

void writeCoverageRowPage(const CoverageStudySettings& settings, const CoverageRow& row, const CoverageScene& scene,
                          const colon::SurfaceCoverage& coverage, const CoverageRowResult& result,
                          const std::string& rendererDescription, const fs::path& folder) {
    ReviewPage page;
    page.title = "Coverage: " + row.name;
    // A file or folder by its absolute path; a volume made in memory (Python) by its description.
    const std::string volume = fs::exists(settings.volumePath) ? fs::absolute(settings.volumePath).string() : settings.volumePath;
    page.facts = {{"volume", volume},
                  {"display", row.display.name},
                  {"map", conformal::mapKindName(row.display.map)},
                  {"directions", coverageDirectionsText(row.directions)},
                  {"renderer", rendererDescription}};
    page.ct = &scene.loaded.volume;
    page.sheetCaption = "the centre eye's walls, unfolded as a cross (floor below the front wall), as coverage saw them";
    for (std::size_t i = 0; i < result.job.poses.size(); ++i) {
        ReviewFrame frame;
        frame.index = static_cast<int>(i);
        frame.pose = result.job.poses[i];
        frame.sheet = frameFolderName(frame.index) + "/sheet.png";
        frame.images.push_back({"centre eye", frame.sheet, ""});
        page.frames.push_back(frame);
    }
    ReviewCoverage review;
    review.percent = coverage.percent();
    review.seenMm2 = coverage.seenAreaMm2();
    review.wallMm2 = coverage.wallAreaMm2();
    review.overview = "coverage.png";
    review.description = rowDescription(settings.coverage);
    review.cumulativePercent = result.cumulativePercent;
    for (std::size_t p = 0; p < result.located.size(); ++p) {
        const PatchView& r = result.located[p];
        review.patches.push_back({static_cast<int>(p) + 1, r.patch.areaMm2, r.patch.centreMm, r.pose, r.nearestFrame, r.picture});
    }
    page.coverage = review;
    page.measurements = {{"frames", std::to_string(result.job.poses.size())},
                         {"unseen patches of " + std::to_string(static_cast<int>(settings.minPatchMm2)) + " mm\u00b2 and more",
                          std::to_string(result.patches.size())}};
    writeReviewPage(folder.string(), page);
}

nlohmann::json coverageCompareEntry(const std::string& rowName, const nlohmann::json& result) {
    return {{"row", rowName},
            {"display", result["display"]},
            {"map", result["map"]},
            {"directions", result["directions"]},
            {"frames", result["frames"]},
            {"coverage_percent", result["coverage_percent"]},
            {"seen_mm2", result["seen_mm2"]},
            {"wall_mm2", result["wall_mm2"]},
            {"unseen_patches", result["unseen_patches"]},
            {"seconds", result["timing"]["seconds"]}};
}

std::string coverageCompareHeader() {
    return "| row | display | map | directions | frames | coverage | unseen patches |\n|---|---|---|---|---:|---:|---:|\n";
}

std::string coverageCompareLine(const std::string& rowName, const nlohmann::json& result) {
    std::ostringstream line;
    line << "| " << rowName << " | " << result["display"].get<std::string>() << " | " << result["map"].get<std::string>()
         << " | " << result["directions"].get<std::string>() << " | " << result["frames"] << " | " << std::fixed
         << std::setprecision(1) << result["coverage_percent"].get<double>() << " % | " << result["unseen_patches"]
         << " |\n";
    return line.str();
}

}  // namespace engine
