/// @brief The colon phantom's text forms (volumes/colon_phantom.h): its ground truth as JSON and
/// its polyp, collapse and fluid-pool specs parsed from command-line text.
#include <charconv>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "volumes/colon_phantom.h"

namespace volumes {

std::string colonTruthJson(const ColonPhantomSpec& spec, const ColonPhantom& phantom) {
    auto vec = [](const glm::dvec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); };
    nlohmann::json truth;
    truth["frame"] = "volume millimetres: voxel (i, j, k) has its centre at (i, j, k) * spacing_mm";
    truth["geometry"] = "analytic signed distances to the centreline polyline, fold ridges, polyp spheres and stalks";
    truth["dims"] = phantom.volume.dims;
    truth["spacing_mm"] = vec(phantom.volume.spacingMm);
    truth["hu"] = {{"lumen", spec.lumenHu}, {"wall_and_tissue", spec.tissueHu}, {"fat", spec.fatHu}};
    truth["noise_sigma_hu"] = spec.noiseSigmaHu;
    truth["seed"] = spec.seed;
    truth["lumen_radius_mm"] = spec.lumenRadiusMm;
    truth["wall_thickness_mm"] = spec.wallThicknessMm;
    truth["fat_thickness_mm"] = spec.fatThicknessMm;
    truth["edge_width_mm"] = spec.edgeWidthMm;
    nlohmann::json centreline = nlohmann::json::array();
    for (const glm::dvec3& p : phantom.centrelineMm) centreline.push_back(vec(p));
    truth["centreline_mm"] = centreline;
    truth["fold_arc_lengths_mm"] = phantom.foldArcLengthsMm;
    truth["fold"] = {{"depth_mm", spec.foldDepthMm}, {"half_width_mm", spec.foldHalfWidthMm}};
    nlohmann::json polyps = nlohmann::json::array();
    for (const PolypTruth& p : phantom.polyps) {
        polyps.push_back({{"kind", polypKindName(p.kind)},
                          {"diameter_mm", 2.0 * p.radiusMm},
                          {"radius_mm", p.radiusMm},
                          {"sphere_radius_mm", p.sphereRadiusMm()},
                          {"height_mm", p.heightMm()},
                          {"on_fold", p.isOnFold},
                          {"centre_mm", vec(p.centreMm)},
                          {"base_mm", vec(p.baseMm)},
                          {"base_normal", vec(p.baseNormal)},
                          {"arc_length_mm", p.arcLengthMm},
                          {"stalk_length_mm", p.stalkLengthMm}});
    }
    truth["polyps"] = polyps;
    if (spec.randomPolypCount > 0) truth["random_polyps"] = {{"count", spec.randomPolypCount}, {"seed", spec.seed}};
    // The phantom's descending-colon end stands for the rectal end.
    truth["centreline_start"] = "caecum";
    truth["centreline_end"] = "rectum";
    truth["centreline_order"] = "caecum_to_rectum";
    // The grid is the patient frame (identity orientation): anterior is -y, the first pose's up.
    truth["anterior"] = vec(volumeDirectionFromPatient(phantom.volume, glm::dvec3(0.0, -1.0, 0.0)));
    truth["shape_seed"] = spec.shapeSeed;
    if (spec.hasBody) {
        truth["body"] = {{"shape", "elliptic cylinder along z, air outside"},
                         {"centre_mm", {phantom.body.centreMm.x, phantom.body.centreMm.y}},
                         {"semi_axes_mm", {phantom.body.semiAxesMm.x, phantom.body.semiAxesMm.y}}};
    }
    if (spec.hasLung) {
        nlohmann::json lungs = nlohmann::json::array();
        for (const LungTruth& lung : phantom.lungs) {
            lungs.push_back({{"side", lung.side},
                             {"shape", "ellipsoid cut by the grid's top face"},
                             {"centre_mm", vec(lung.centreMm)},
                             {"semi_axes_mm", vec(lung.semiAxesMm)},
                             {"hu", spec.lungHu}});
        }
        truth["lungs"] = lungs;
        truth["lung_hu"] = spec.lungHu;
        truth["lung_clearance_mm"] = phantom.lungClearanceMm;
    }
    if (!phantom.collapsedArcMm.empty()) truth["collapsed_arc_mm"] = phantom.collapsedArcMm;
    if (!phantom.fluidPools.empty()) {
        nlohmann::json pools = nlohmann::json::array();
        for (const FluidPoolTruth& pool : phantom.fluidPools) {
            pools.push_back({{"arc_mm", {pool.startArcMm, pool.endArcMm}},
                             {"level_y_mm", pool.levelYMm},
                             {"hu", spec.fluidHu}});
        }
        truth["fluid_pools"] = pools;
        truth["fluid_hu"] = spec.fluidHu;
    }
    return truth.dump(1) + "\n";
}

namespace {

/// Splits "a:b:c" at colons into at most `maxFields + 1` parts (one too many says "too many").
std::vector<std::string> splitFields(const std::string& text, std::size_t maxFields) {
    std::vector<std::string> parts;
    std::size_t start = 0;
    while (parts.size() <= maxFields) {
        const std::size_t end = text.find(':', start);
        parts.push_back(text.substr(start, end == std::string::npos ? std::string::npos : end - start));
        if (end == std::string::npos) break;
        start = end + 1;
    }
    return parts;
}

/// The whole of `field` as a finite number, or nullopt.
std::optional<double> parseNumber(const std::string& field) {
    double value = 0.0;
    const auto result = std::from_chars(field.data(), field.data() + field.size(), value);
    if (field.empty() || result.ec != std::errc{} || result.ptr != field.data() + field.size() || !std::isfinite(value))
        return std::nullopt;
    return value;
}

/// Parses POSITION[:NUMBER...] for the collapse and pool options: `names` says what each
/// field is, `values` holds the defaults and receives what the text gives.
void parsePositionFields(const std::string& text, const std::string& what, const std::string& usage,
                         const std::vector<std::string>& names, std::vector<double>& values) {
    auto failSpec = [&](const std::string& problem) {
        throw VolumeError(what + " '" + text + "': " + problem + " (expected " + usage + ")");
    };
    const std::vector<std::string> parts = splitFields(text, names.size());
    if (parts.size() > names.size()) failSpec("has more than " + std::to_string(names.size()) + " fields");
    for (std::size_t i = 0; i < parts.size(); ++i) {
        const std::optional<double> value = parseNumber(parts[i]);
        if (!value) failSpec(names[i] + " '" + parts[i] + "' is not a number");
        values[i] = *value;
    }
    if (values[0] < 0.0 || values[0] > 1.0) failSpec("position must be 0..1 along the centreline");
    for (std::size_t i = 1; i < values.size(); ++i) {
        if (!(values[i] > 0.0)) failSpec(names[i] + " must be positive");
    }
}

}  // namespace

CollapseSpec parseCollapseSpec(const std::string& text) {
    CollapseSpec spec;
    std::vector<double> values{spec.arcFraction, spec.lengthMm};
    parsePositionFields(text, "collapse", "POSITION[:LENGTH_MM], e.g. 0.42:12", {"position", "length"}, values);
    spec.arcFraction = values[0];
    spec.lengthMm = values[1];
    return spec;
}

FluidPoolSpec parseFluidPoolSpec(const std::string& text) {
    FluidPoolSpec spec;
    std::vector<double> values{spec.arcFraction, spec.lengthMm, spec.depthMm};
    parsePositionFields(text, "fluid pool", "POSITION[:LENGTH_MM[:DEPTH_MM]], e.g. 0.238:40:6",
                        {"position", "length", "depth"}, values);
    spec.arcFraction = values[0];
    spec.lengthMm = values[1];
    spec.depthMm = values[2];
    return spec;
}

PolypSpec parsePolypSpec(const std::string& text) {
    auto failSpec = [&](const std::string& problem) {
        throw VolumeError("polyp '" + text + "': " + problem +
                          " (expected KIND:DIAMETER_MM:POSITION:ANGLE_DEG[:STALK_MM], KIND sessile, pedunculated or "
                          "flat, e.g. sessile:6:0.3:45)");
    };
    std::vector<std::string> parts;
    std::size_t start = 0;
    while (parts.size() < 6) {
        const std::size_t end = text.find(':', start);
        parts.push_back(text.substr(start, end == std::string::npos ? std::string::npos : end - start));
        if (end == std::string::npos) break;
        start = end + 1;
    }
    if (parts.size() < 4 || parts.size() > 5) failSpec("needs 4 or 5 fields");
    PolypSpec spec;
    if (parts[0] == "sessile") {
        spec.kind = PolypKind::Sessile;
    } else if (parts[0] == "pedunculated") {
        spec.kind = PolypKind::Pedunculated;
    } else if (parts[0] == "flat") {
        spec.kind = PolypKind::Flat;
    } else {
        failSpec("kind '" + parts[0] + "' is not sessile, pedunculated or flat");
    }
    auto number = [&](const std::string& field, const char* what) {
        double value = 0.0;
        const auto result = std::from_chars(field.data(), field.data() + field.size(), value);
        if (field.empty() || result.ec != std::errc{} || result.ptr != field.data() + field.size() ||
            !std::isfinite(value)) {
            failSpec(std::string(what) + " '" + field + "' is not a number");
        }
        return value;
    };
    spec.diameterMm = number(parts[1], "diameter");
    spec.arcFraction = number(parts[2], "position");
    spec.angleDeg = number(parts[3], "angle");
    if (parts.size() == 5) spec.stalkLengthMm = number(parts[4], "stalk length");
    if (spec.diameterMm < 3.0 || spec.diameterMm > 15.0) failSpec("diameter must be 3..15 mm");
    if (spec.arcFraction < 0.0 || spec.arcFraction > 1.0) failSpec("position must be 0..1 along the centreline");
    return spec;
}

}  // namespace volumes
