#include "engine/studies/polyp_check_report.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include "engine/output/png_writer.h"
#include "engine/output/text_file.h"

namespace engine {
namespace {

namespace fs = std::filesystem;

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

nlohmann::json predictedJson(const PredictedErrors& errors) {
    return {{"found", errors.isFound},
            {"aspect_error", numberOrNull(errors.aspectError)},
            {"circularity_error", numberOrNull(errors.circularityError)},
            {"grid_angle_error_deg", numberOrNull(errors.gridAngleErrorDeg)}};
}

/// The poses and the eye's distance rule as applied (PolypCheckPlan).
nlohmann::json planJson(const PolypCheckPlan& plan, const PolypCheckJob& job) {
    nlohmann::json poses = nlohmann::json::array();
    for (const auto& target : plan.poses) {
        const glm::dvec2 elevationAzimuth = elevationAzimuthDegOf(target.pose.directionCave);
        const glm::dvec3& d = target.pose.directionCave;
        poses.push_back({{"name", target.pose.name},
                         {"direction_cave", {d.x, d.y, d.z}},
                         {"elevation_deg", elevationAzimuth.x},
                         {"azimuth_deg", elevationAzimuth.y},
                         {"missing_wall", missingWallOf(job.display, d).empty()
                                              ? nlohmann::json()
                                              : nlohmann::json(missingWallOf(job.display, d))},
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

std::string percent(double fraction) {
    if (!std::isfinite(fraction)) return "–";
    std::ostringstream text;
    text << std::fixed << std::setprecision(1) << 100.0 * fraction << " %";
    return text.str();
}

double numberOrNan(const nlohmann::json& value) {
    return value.is_number() ? value.get<double>() : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

nlohmann::json polypResultEntries(const std::vector<PolypViewResult>& results, const PolypCheckPlan& plan) {
    nlohmann::json list = nlohmann::json::array();
    std::map<std::string, const PolypPose*> poseByName;
    for (const auto& target : plan.poses) poseByName[target.pose.name] = &target.pose;
    for (const auto& r : results) {
        const glm::dvec2 elevationAzimuth = elevationAzimuthDegOf(poseByName.at(r.pose)->directionCave);
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
                        {"eye", eyeText(r.eye)},
                        {"map", mapName(r.map)},
                        {"warp", warpModeName(r.warp)},
                        {"visible", r.isVisible},
                        {"visible_fraction", numberOrNull(r.visibleFraction)},
                        {"pixels", r.view.pixels},
                        {"pixels_across", r.view.pixelsAcross},
                        {"reference_pixels", r.reference.pixels},
                        {"reference_unoccluded_share", r.referenceUnoccludedShare},
                        {"reference_hidden_in_front_share", r.referenceHiddenInFrontShare},
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

nlohmann::json polypCheckDocument(const nlohmann::json& list, const PolypCheckSources& sources,
                                  const PolypCheckJob& job, const PolypCheckPlan& plan) {
    nlohmann::json doc;
    // A file or folder by its absolute path; a volume made in memory (Python) by its description.
    doc["volume"] = fs::exists(sources.volumePath) ? fs::absolute(sources.volumePath).string() : sources.volumePath;
    doc["truth"] = fs::absolute(sources.truthPath).string();
    doc["display"] = job.display.name;
    doc["walls"] = nlohmann::json::array();
    for (const auto& wall : job.display.walls) {
        doc["walls"].push_back({{"name", wallNameText(wall.name)}, {"width", wall.width}, {"height", wall.height}});
    }
    doc["warp"] = sources.warpName;
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

std::string polypCheckMarkdown(const nlohmann::json& entries) {
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

void writePolypCrops(const std::vector<PolypViewResult>& results, const fs::path& folder, int cropSize) {
    std::map<std::tuple<int, std::string, Eye>, std::vector<const PolypViewResult*>> rows;
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
        const fs::path file = folder / ("polyp_" + std::to_string(polyp) + "_" + pose + "_" + eyeText(eye) + ".png");
        writePng(file.string(), width, cropSize, rgba, true);
    }
}


std::vector<nlohmann::json> polypEntriesInOrder(const std::vector<std::string>& entryLists, const PolypCheckJob& job,
                                                const PolypCheckPlan& plan) {
    std::vector<nlohmann::json> ordered;
    for (const std::string& text : entryLists) {
        for (auto& entry : nlohmann::json::parse(text)) ordered.push_back(std::move(entry));
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
    std::stable_sort(ordered.begin(), ordered.end(),
                     [&](const nlohmann::json& a, const nlohmann::json& b) { return keyOf(a) < keyOf(b); });
    return ordered;
}

std::string polypCheckWorstText(const nlohmann::json& document) {
    std::ostringstream text;
    for (const char* key : {"worst_aspect_error", "worst_circularity_error"}) {
        text << key << " (polyps >= 6 mm on the missing walls, targeted poses):";
        for (const auto& [map, value] : document[key].items()) {
            text << ' ' << map << ' ' << percent(value.is_number() ? value.get<double>() : NAN);
        }
        text << '\n';
    }
    return text.str();
}

void requirePolypCheckFolder(const std::filesystem::path& folder, bool force) {
    namespace fs = std::filesystem;
    if (fs::exists(folder) && !fs::is_directory(folder)) throw std::runtime_error(folder.string() + ": is not a folder");
    const bool holdsACheck =
        fs::exists(folder / "polyp_check.json") || fs::exists(folder / "polyp_check.md") || fs::exists(folder / "crops");
    if (!force && holdsACheck) {
        throw std::runtime_error(folder.string() + ": holds an earlier polyp check (use --force to replace it)");
    }
}

void writePolypCheckFiles(const std::filesystem::path& folder, const nlohmann::json& document) {
    std::filesystem::create_directories(folder);
    writeTextFile(folder / "polyp_check.json", document.dump(1) + "\n");
    writeTextFile(folder / "polyp_check.md", polypCheckMarkdown(document["results"]));
}

}  // namespace engine
