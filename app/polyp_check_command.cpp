/// @brief `cvc polyp-check`: the polyp-shape regression suite. Every polyp of a ground truth is
/// seen from poses along its path that put it on a wall, near the missing walls' edge, on their
/// directions and toward a slit tip, for the left, centre and right eyes, through the conformal
/// map, the linear baseline and no map, and measured as the viewer sees it against a pinhole
/// reference, beside what the map alone predicts (engine/display/polyp_check.h). Writes a
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
#include "app/mpi_session.h"
#include "app/option_parsing.h"
#include "app/progress_bar.h"
#include "colon/polyp_truth.h"
#include "engine/core/gpu_context.h"
#include "engine/display/display_json.h"
#include "engine/display/display_map.h"
#include "engine/display/polyp_check.h"
#include "engine/output/png_writer.h"
#include "engine/render/volume_texture.h"
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

nlohmann::json numberOrNull(double value) { return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(); }

std::string mapName(conformal::MapKind kind) { return conformal::mapKindName(kind); }

/// The worst error (`key` of the result entries) of each map over polyps of 6 mm and more seen
/// on the missing walls' directions at the targeted poses, every eye.
nlohmann::json worstOf(const nlohmann::json& entries, const char* key) {
    std::map<std::string, double> worst;
    for (const auto& r : entries) {
        if (r["diameter_mm"].get<double>() < 6.0 || r["missing_wall"].is_null() || !r["targeted"].get<bool>() ||
            r["map"] == "none") {
            continue;
        }
        const double value = r[key].is_number() ? r[key].get<double>() : std::numeric_limits<double>::quiet_NaN();
        double& slot = worst.try_emplace(r["map"].get<std::string>(), 0.0).first->second;
        slot = std::isfinite(value) ? std::max(slot, value) : std::numeric_limits<double>::infinity();
    }
    nlohmann::json out = nlohmann::json::object();
    for (const auto& [map, value] : worst) out[map] = numberOrNull(value);
    return out;
}

nlohmann::json predictedJson(const engine::PredictedErrors& errors) {
    return {{"found", errors.isFound},
            {"aspect_error", numberOrNull(errors.aspectError)},
            {"circularity_error", numberOrNull(errors.circularityError)},
            {"grid_angle_error_deg", numberOrNull(errors.gridAngleErrorDeg)}};
}

/// One JSON entry per result, in the results' order.
nlohmann::json resultEntries(const std::vector<engine::PolypViewResult>& results, const engine::PolypCheckPlan& plan) {
    nlohmann::json list = nlohmann::json::array();
    std::map<std::string, const engine::PolypPose*> poseByName;
    for (const auto& target : plan.poses) poseByName[target.pose.name] = &target.pose;
    for (const auto& r : results) {
        const glm::dvec2 elevationAzimuth = engine::elevationAzimuthDegOf(poseByName.at(r.pose)->directionCave);
        list.push_back({{"polyp", r.polyp},
                        {"diameter_mm", r.diameterMm},
                        {"pose", r.pose},
                        {"elevation_deg", elevationAzimuth.x},
                        {"azimuth_deg", elevationAzimuth.y},
                        {"targeted", r.isTargeted},
                        {"untargeted_because",
                         r.untargetedBecause.empty() ? nlohmann::json() : nlohmann::json(r.untargetedBecause)},
                        {"angular_radius_deg", r.angularRadiusDeg},
                        {"singular_distance_deg", r.singularDistanceDeg},
                        {"missing_wall", r.missingWall.empty() ? nlohmann::json() : nlohmann::json(r.missingWall)},
                        {"eye", engine::eyeText(r.eye)},
                        {"map", mapName(r.map)},
                        {"warp", engine::warpModeName(r.warp)},
                        {"visible", r.isVisible},
                        {"visible_fraction", numberOrNull(r.visibleFraction)},
                        {"pixels", r.view.pixels},
                        {"pixels_across", r.view.pixelsAcross},
                        {"reference_pixels", r.reference.pixels},
                        {"reference_unoccluded_share", r.referenceUnoccludedShare},
                        {"aspect", r.view.aspect},
                        {"reference_aspect", r.reference.aspect},
                        {"orientation_deg", r.view.orientationDeg},
                        {"circularity", r.view.circularity},
                        {"reference_circularity", r.reference.circularity},
                        {"grid_angle_deg", r.view.gridAngleDeg},
                        {"reference_grid_angle_deg", r.reference.gridAngleDeg},
                        {"aspect_error", numberOrNull(r.aspectError)},
                        {"circularity_error", numberOrNull(r.circularityError)},
                        {"grid_angle_error_deg", numberOrNull(r.gridAngleErrorDeg)},
                        {"predicted", predictedJson(r.predicted)},
                        {"predicted_circle", predictedJson(r.predictedCircle)},
                        {"predicted_floor", predictedJson(r.predictedFloor)},
                        {"centre_aspect_error", numberOrNull(r.centreAspectError)},
                        {"exact_warp_aspect_error", numberOrNull(r.exactWarpAspectError)},
                        {"apart_from_prediction_because",
                         r.apartBecause.empty() ? nlohmann::json() : nlohmann::json(r.apartBecause)},
                        {"position_mm", {r.cameraPose.positionMm.x, r.cameraPose.positionMm.y, r.cameraPose.positionMm.z}},
                        {"forward", {r.cameraPose.forward.x, r.cameraPose.forward.y, r.cameraPose.forward.z}},
                        {"up", {r.cameraPose.up.x, r.cameraPose.up.y, r.cameraPose.up.z}}});
    }
    return list;
}

/// The poses and the eye's distance rule as applied (PolypCheckPlan).
nlohmann::json planJson(const engine::PolypCheckPlan& plan, const engine::PolypCheckJob& job) {
    nlohmann::json poses = nlohmann::json::array();
    for (const auto& target : plan.poses) {
        const glm::dvec2 elevationAzimuth = engine::elevationAzimuthDegOf(target.pose.directionCave);
        const glm::dvec3& d = target.pose.directionCave;
        poses.push_back({{"name", target.pose.name},
                         {"direction_cave", {d.x, d.y, d.z}},
                         {"elevation_deg", elevationAzimuth.x},
                         {"azimuth_deg", elevationAzimuth.y},
                         {"missing_wall", engine::missingWallOf(job.display, d).empty()
                                              ? nlohmann::json()
                                              : nlohmann::json(engine::missingWallOf(job.display, d))},
                         {"targeted", target.isTargeted},
                         {"predicted_floor", predictedJson(target.floor)}});
    }
    return {{"poses", poses},
            {"angular_radius_deg", plan.angularRadiusDeg},
            {"widest_angular_radius_deg", plan.widestAngularRadiusDeg},
            {"rule",
             "a pose is targetable when the conformal map's predicted aspect and circularity errors for a circle at the "
             "least angular radius (its floor) are within the predicted target; each polyp's eyes stand where it "
             "subtends the largest angular radius up to the most, in quarter degrees down to the least, from which it is "
             "in full view and the predictions for its own outline and for a circle of that radius meet the target at "
             "every targetable pose; a result is targeted where its pose is targetable, some place on its path shows "
             "the polyp in full view, and those two predictions from the polyp's place meet the target"},
            {"least_angular_radius_deg", job.minAngularRadiusDeg},
            {"most_angular_radius_deg", job.angularRadiusDeg},
            {"predicted_target", job.predictedTarget}};
}

/// The check's document (polyp_check.json) around the result entries.
nlohmann::json resultsJson(const nlohmann::json& list, const PolypCheckOptions& options,
                           const engine::PolypCheckJob& job, const engine::PolypCheckPlan& plan) {
    nlohmann::json doc;
    doc["volume"] = fs::absolute(options.volumePath).string();
    doc["truth"] = fs::absolute(options.truthPath).string();
    doc["display"] = job.display.name;
    doc["walls"] = nlohmann::json::array();
    for (const auto& wall : job.display.walls) {
        doc["walls"].push_back({{"name", engine::wallNameText(wall.name)}, {"width", wall.width}, {"height", wall.height}});
    }
    doc["warp"] = options.warp;
    doc["plan"] = planJson(plan, job);
    doc["mm_per_metre"] = job.mmPerMetre;
    doc["tolerance_mm"] = job.toleranceMm;
    doc["min_polyp_pixels"] = colon::kMinPolypPixels;
    doc["results"] = list;
    doc["worst_aspect_error"] = worstOf(list, "aspect_error");
    doc["worst_circularity_error"] = worstOf(list, "circularity_error");
    doc["worst_grid_angle_error_deg"] = worstOf(list, "grid_angle_error_deg");
    doc["worst_over"] = "polyps of 6 mm and more whose direction falls on a missing wall, targeted poses, every eye";
    return doc;
}

std::string percent(double fraction) {
    if (!std::isfinite(fraction)) return "–";
    std::ostringstream text;
    text << std::fixed << std::setprecision(1) << 100.0 * fraction << " %";
    return text.str();
}

double numberOrNan(const nlohmann::json& value) {
    return value.is_number() ? value.get<double>() : std::numeric_limits<double>::quiet_NaN();
}

std::string markdownTable(const nlohmann::json& entries) {
    std::ostringstream md;
    md << "| polyp | mm | pose | missing wall | eye | map | visible | px across | aspect error | predicted | "
          "circularity error | grid angle error |\n|---:|---:|---|---|---|---|---|---:|---:|---:|---:|---:|\n";
    for (const auto& r : entries) {
        const std::string map = r["map"].get<std::string>();
        md << "| " << r["polyp"].get<int>() << " | " << r["diameter_mm"].get<double>() << " | "
           << r["pose"].get<std::string>()
           << (r["targeted"].get<bool>() ? "" : " (no target: " + r["untargeted_because"].get<std::string>() + ")")
           << " | "
           << (r["missing_wall"].is_null() ? std::string("–") : r["missing_wall"].get<std::string>()) << " | "
           << r["eye"].get<std::string>() << " | " << map << " | "
           << (r["visible"].get<bool>() ? "yes"
               : map == "none"           ? "cut off (" + percent(numberOrNan(r["visible_fraction"])) + ")"
                                         : "no")
           << " | " << std::fixed << std::setprecision(0) << r["pixels_across"].get<double>() << " | "
           << percent(numberOrNan(r["aspect_error"])) << " | " << percent(numberOrNan(r["predicted"]["aspect_error"]))
           << " | " << percent(numberOrNan(r["circularity_error"])) << " | ";
        const double gridError = numberOrNan(r["grid_angle_error_deg"]);
        if (std::isfinite(gridError)) {
            md << std::setprecision(2) << gridError << "°";
        } else {
            md << "–";
        }
        md << " |\n";
        md.unsetf(std::ios::fixed);
        md << std::setprecision(6);
    }
    return md.str();
}

/// Reference | conformal | linear | none crops of one polyp, pose and eye, side by side.
void writeCrops(const std::vector<engine::PolypViewResult>& results, const fs::path& folder, int cropSize) {
    std::map<std::tuple<int, std::string, engine::Eye>, std::vector<const engine::PolypViewResult*>> rows;
    for (const auto& r : results) rows[{r.polyp, r.pose, r.eye}].push_back(&r);
    const int gap = 4;
    for (const auto& [key, views] : rows) {
        const int columns = 1 + static_cast<int>(views.size());
        const int width = columns * cropSize + (columns - 1) * gap;
        std::vector<uint8_t> rgba(static_cast<std::size_t>(width) * static_cast<std::size_t>(cropSize) * 4, 255);
        const auto paste = [&](const colon::RgbaImage& crop, int column) {
            if (crop.width != cropSize) return;  // nothing seen: left white
            for (int row = 0; row < cropSize; ++row) {
                std::copy_n(crop.rgba.begin() + static_cast<std::ptrdiff_t>(row) * cropSize * 4, cropSize * 4,
                            rgba.begin() + (static_cast<std::ptrdiff_t>(row) * width + column * (cropSize + gap)) * 4);
            }
        };
        paste(views.front()->referenceCrop, 0);
        for (std::size_t v = 0; v < views.size(); ++v) paste(views[v]->crop, static_cast<int>(v) + 1);
        const auto& [polyp, pose, eye] = key;
        const fs::path file = folder / ("polyp_" + std::to_string(polyp) + "_" + pose + "_" + engine::eyeText(eye) + ".png");
        engine::writePng(file.string(), width, cropSize, rgba, true);
    }
}

/// The display's poses named in `names` (all of them for none), in the display's order; throws
/// std::invalid_argument naming an unknown pose and listing the display's.
std::vector<engine::PolypPose> chosenPoses(const engine::Display& display, const std::vector<std::string>& names) {
    const std::vector<engine::PolypPose> all = engine::polypPosesFor(display);
    if (names.empty()) return all;
    for (const std::string& name : names) {
        if (std::none_of(all.begin(), all.end(), [&](const engine::PolypPose& pose) { return pose.name == name; })) {
            std::string known;
            for (const auto& pose : all) known += (known.empty() ? "" : ", ") + pose.name;
            throw std::invalid_argument("--poses: display '" + display.name + "' has no pose '" + name + "' (it has " +
                                        known + ")");
        }
    }
    std::vector<engine::PolypPose> chosen;
    for (const auto& pose : all) {
        if (std::find(names.begin(), names.end(), pose.name) != names.end()) chosen.push_back(pose);
    }
    return chosen;
}

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
    MpiSession& mpi = mpiSession();
    if (mpi.rank() == 0) {
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
    job.poses = chosenPoses(display, options.poses);
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
    if (mpi.rank() == 0) loadMaps();
    mpi.barrier();
    if (mpi.rank() != 0) loadMaps();

    // This rank's polyps: the r-th, the (r + N)-th, ... of those asked for.
    engine::PolypCheckJob mine = job;
    mine.polypIndices.clear();
    for (std::size_t i = 0; i < job.polypIndices.size(); ++i) {
        if (static_cast<int>(i % static_cast<std::size_t>(mpi.ranks())) == mpi.rank()) mine.polypIndices.push_back(job.polypIndices[i]);
    }
    std::optional<ProgressBar> progress;
    const auto onProgress = [&progress, &mpi](int done, int total) {
        if (mpi.rank() != 0) return;  // rank 0 shows its share
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
    writeCrops(results, crops, job.cropSize);

    // Rank 0 puts every rank's entries in the order one process gives them: map, polyp (as
    // asked for), pose, eye.
    const std::vector<std::string> all = mpi.gather(resultEntries(results, plan).dump());
    mpi.barrier();
    if (mpi.rank() != 0) return;
    nlohmann::json list = nlohmann::json::array();
    for (const std::string& text : all) {
        for (auto& entry : nlohmann::json::parse(text)) list.push_back(std::move(entry));
    }
    const auto positionOf = [](const auto& sequence, const auto& value) {
        return static_cast<std::size_t>(std::find(sequence.begin(), sequence.end(), value) - sequence.begin());
    };
    std::vector<std::string> mapOrder, poseOrder;
    for (conformal::MapKind kind : job.maps) mapOrder.push_back(mapName(kind));
    for (const auto& target : plan.poses) poseOrder.push_back(target.pose.name);
    const std::vector<std::string> eyeOrder{"left", "centre", "right"};
    const auto keyOf = [&](const nlohmann::json& r) {
        return std::make_tuple(positionOf(mapOrder, r["map"].get<std::string>()),
                               positionOf(job.polypIndices, r["polyp"].get<int>()),
                               positionOf(poseOrder, r["pose"].get<std::string>()),
                               positionOf(eyeOrder, r["eye"].get<std::string>()));
    };
    std::vector<nlohmann::json> ordered(list.begin(), list.end());
    std::stable_sort(ordered.begin(), ordered.end(),
                     [&](const nlohmann::json& a, const nlohmann::json& b) { return keyOf(a) < keyOf(b); });
    const nlohmann::json doc = resultsJson(nlohmann::json(ordered), options, job, plan);
    writeTextFile(jsonFile.string(), doc.dump(1) + "\n");
    if (!options.jsonPath.empty()) writeTextFile(options.jsonPath, doc.dump(1) + "\n");
    writeTextFile(tableFile.string(), markdownTable(doc["results"]));

    std::cout << "checked " << job.polypIndices.size() << " polyp(s) x " << plan.poses.size() << " poses x 3 eyes x "
              << job.maps.size() << " maps on " << context.driverDescription() << "; eyes where polyps subtend "
              << plan.angularRadiusDeg << " degrees\n";
    for (const char* key : {"worst_aspect_error", "worst_circularity_error"}) {
        std::cout << key << " (polyps >= 6 mm on the missing walls, targeted poses):";
        for (const auto& [map, value] : doc[key].items()) std::cout << ' ' << map << ' ' << percent(value.is_number() ? value.get<double>() : NAN);
        std::cout << '\n';
    }
    std::cout << "wrote " << options.outFolder << '\n';
}

}  // namespace

void addPolypCheckCommand(CLI::App& program) {
    auto options = std::make_shared<PolypCheckOptions>();
    CLI::App* command = program.add_subcommand(
        "polyp-check", "Check that polyps keep their shape through the display's map: each seen on a wall, at the "
                       "ceiling's edge, on the ceiling and toward a corner, against a pinhole reference");
    command
        ->add_option("volume,--volume", options->volumePath,
                     "Volume: DICOM folder, .nrrd/.nhdr, .nii/.nii.gz, .mha/.mhd, .vdb, or raw with --raw")
        ->required();
    command->add_option("--raw", options->rawSpec, "Describe a headerless raw file, e.g. 512x512x451:int16:0.7x0.7x1.25");
    command->add_option("--truth", options->truthPath,
                        "Ground truth with polyps and a centreline (cvc phantom's JSON, or cvc insert-polyp's)")
        ->required();
    command->add_option("--display", options->display, "Display preset or JSON file with a missing wall")->capture_default_str();
    command->add_option("--polyps", options->polyps, "Polyps to check, by index in the truth (default: all)")
        ->delimiter(',');
    command->add_option("--poses", options->poses,
                        "Poses to check, by name (default: all of the display's; the names are in polyp_check.json)")
        ->delimiter(',');
    command->add_option("--maps", options->maps, "Maps to check: conformal (always), linear, none")
        ->delimiter(',')
        ->check(CLI::IsMember({"conformal", "linear", "none"}))
        ->capture_default_str();
    command->add_option("-o,--out", options->outFolder, "Output folder")->required();
    command->add_option("--json", options->jsonPath, "Also write the results' JSON to this file");
    command->add_option("--wall-size", options->wallSize,
                        "Front wall size WIDTHxHEIGHT in pixels, the other walls at the same density (default: the "
                        "display's)");
    command->add_option("--map-size", options->mapSize, "Cube-map face size of the baked maps")->capture_default_str();
    command->add_option("--scale", options->mmPerMetre, "Volume millimetres per CAVE metre")->capture_default_str();
    command->add_option("--warp", options->warp, "eye-centred (the display default), polyline, chord or exact")
        ->check(CLI::IsMember(engine::bendingWarpModeNames()))
        ->capture_default_str();
    command->add_option("--angular-radius", options->angularRadiusDeg,
                        "The polyp's angular radius from the eye in degrees, at most: the eye comes as close as the "
                        "map's predicted error at the targeted poses allows (down to 3 degrees)")
        ->check(CLI::Range(1.0, 30.0))
        ->capture_default_str();
    command->add_option("--device", options->device, "Vulkan device: an index, part of its name, cpu or gpu");
    command->add_flag("--force", options->force, "Replace an earlier check in the output folder");
    command->callback([options] { runPolypCheck(*options); });
}

}  // namespace app
