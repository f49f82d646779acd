/// @brief `cvc insert-polyp`: a synthetic polyp inserted into a scan on the colon wall nearest a
/// point (colon/polyp_insertion.h), written with its ground truth in the colon phantom's JSON
/// form, so detection and rendering can be scored on real anatomy as on the phantom.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <memory>
#include <set>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "app/option_groups.h"
#include "app/option_parsing.h"
#include "colon/polyp_insertion.h"
#include "engine/sequence/camera_path.h"
#include "volumes/load_volume.h"
#include "volumes/nrrd_io.h"

namespace app {
namespace {

namespace fs = std::filesystem;

struct InsertPolypOptions {
    std::string volumePath;
    std::string rawSpec;
    std::string outPath;
    std::string truthPath;       // default: the output path with .json
    std::string centrelinePath;  // a colon.json or a phantom truth: its centreline (and polyps) go into the truth
    std::string jsonPath;
    std::vector<double> atMm;
    double diameterMm = 0.0;
    double stalkLengthMm = 0.0;
    bool force = false;
};

nlohmann::json vec(const glm::dvec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); }

/// The fields of a centreline file that make the truth usable as `cvc render --path`.
const char* const kCentrelineKeys[] = {"centreline_mm", "segment_starts", "centreline_order", "anterior"};

nlohmann::json readCentrelineFile(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error(path + ": cannot be read (--centreline)");
    nlohmann::json doc;
    try {
        doc = nlohmann::json::parse(in);
    } catch (const nlohmann::json::exception& e) {
        throw std::runtime_error(path + ": not JSON (--centreline): " + e.what());
    }
    if (!doc.is_object() || !doc.contains("centreline_mm") || !doc["centreline_mm"].is_array()) {
        throw std::runtime_error(path + ": no \"centreline_mm\" list (--centreline wants a colon.json from `cvc colon` "
                                        "or a phantom truth)");
    }
    if (doc.contains("polyps") && !doc["polyps"].is_array()) {
        throw std::runtime_error(path + ": \"polyps\" is not a list");
    }
    // The path reader (fuzzed) checks every point and segment start, so that the walk along the
    // file's own order below reads them without checks of its own.
    (void)engine::readCentreline(path);
    return doc;
}

/// The centreline file must describe this volume's grid, or its millimetres mean something else.
void requireSameGrid(const nlohmann::json& doc, const volumes::Volume& volume, const std::string& path) {
    if (!doc.contains("dims")) return;
    const nlohmann::json dims = volume.dims;
    if (doc["dims"] != dims) {
        throw std::runtime_error(path + " describes a " + doc["dims"].dump() + " grid, the volume is " + dims.dump());
    }
}

/// Arc length along the centreline polyline to its point nearest `pointMm`, from its first point;
/// the jumps between segments (at "segment_starts") are not part of the path and not counted.
double arcLengthMm(const nlohmann::json& doc, const glm::dvec3& pointMm) {
    std::vector<glm::dvec3> line;
    for (const auto& p : doc["centreline_mm"]) {
        if (!p.is_array() || p.size() != 3) return 0.0;
        line.emplace_back(p[0].get<double>(), p[1].get<double>(), p[2].get<double>());
    }
    std::set<std::size_t> starts;
    if (doc.contains("segment_starts")) {
        for (const auto& s : doc["segment_starts"]) starts.insert(s.get<std::size_t>());
    }
    double walked = 0.0, bestArc = 0.0, bestDistance = std::numeric_limits<double>::max();
    for (std::size_t n = 0; n < line.size(); ++n) {
        const double distance = glm::length(pointMm - line[n]);
        if (distance < bestDistance) bestDistance = distance, bestArc = walked;
        if (n + 1 == line.size() || starts.count(n + 1) != 0) continue;
        const glm::dvec3 step = line[n + 1] - line[n];
        const double length = glm::length(step);
        if (length > 0.0) {
            const double t = std::clamp(glm::dot(pointMm - line[n], step) / (length * length), 0.0, 1.0);
            const double along = glm::length(pointMm - (line[n] + t * step));
            if (along < bestDistance) bestDistance = along, bestArc = walked + t * length;
        }
        walked += length;
    }
    return bestArc;
}

nlohmann::json polypJson(const colon::InsertedPolyp& polyp, double arcMm) {
    const volumes::PolypTruth& t = polyp.truth;
    return {{"kind", t.kind == volumes::PolypKind::Sessile ? "sessile" : "pedunculated"},
            {"diameter_mm", 2.0 * t.radiusMm},
            {"radius_mm", t.radiusMm},
            {"centre_mm", vec(t.centreMm)},
            {"base_mm", vec(t.baseMm)},
            {"base_normal", vec(t.baseNormal)},
            {"arc_length_mm", arcMm},
            {"stalk_length_mm", t.stalkLengthMm},
            {"tissue_hu", polyp.tissueHu},
            {"edge_width_mm", polyp.edgeWidthMm}};
}

/// The truth in the phantom's form; with a centreline file, its path and earlier polyps too.
nlohmann::json truthJson(const InsertPolypOptions& options, const volumes::Volume& volume,
                         const nlohmann::json& centreline, const nlohmann::json& polyp) {
    nlohmann::json truth;
    truth["frame"] = "volume millimetres: voxel (i, j, k) has its centre at (i, j, k) * spacing_mm";
    truth["geometry"] = "synthetic polyps inserted by cvc insert-polyp: spheres (and capsule stalks) on the scanned wall";
    truth["source_volume"] = fs::absolute(options.volumePath).string();
    truth["volume"] = fs::absolute(options.outPath).string();
    truth["dims"] = volume.dims;
    truth["spacing_mm"] = vec(volume.spacingMm);
    nlohmann::json polyps = nlohmann::json::array();
    if (!centreline.is_null()) {
        truth["centreline_source"] = fs::absolute(options.centrelinePath).string();
        for (const char* key : kCentrelineKeys) {
            if (centreline.contains(key)) truth[key] = centreline[key];
        }
        if (centreline.contains("polyps")) polyps = centreline["polyps"];  // stacked insertions keep the earlier ones
    }
    polyps.push_back(polyp);
    truth["polyps"] = polyps;
    return truth;
}

void runInsertPolyp(const InsertPolypOptions& options) {
    colon::PolypInsertion request;
    request.atMm = vec3From(options.atMm, "--at");
    request.diameterMm = options.diameterMm;
    request.stalkLengthMm = options.stalkLengthMm;
    const std::string truthPath =
        options.truthPath.empty() ? fs::path(options.outPath).replace_extension(".json").string() : options.truthPath;
    if (fs::absolute(truthPath) == fs::absolute(options.outPath)) {
        throw std::invalid_argument("the truth file " + truthPath + " would replace the output volume (give --truth)");
    }
    requireWritableOutput(options.outPath, options.force);
    requireWritableOutput(truthPath, options.force);
    if (!options.jsonPath.empty()) requireWritableOutput(options.jsonPath, options.force);
    const nlohmann::json centreline =
        options.centrelinePath.empty() ? nlohmann::json() : readCentrelineFile(options.centrelinePath);

    volumes::LoadOptions load;
    if (!options.rawSpec.empty()) load.raw = volumes::parseRawSpec(options.rawSpec);
    std::cerr << "insert-polyp: loading " << options.volumePath << '\n';
    volumes::Volume volume = volumes::loadVolume(options.volumePath, load);
    if (!centreline.is_null()) requireSameGrid(centreline, volume, options.centrelinePath);
    const colon::InsertedPolyp polyp = colon::insertPolyp(volume, request);
    std::cerr << std::fixed << std::setprecision(0) << "insert-polyp: the wall at the base goes from " << polyp.airHu
              << " HU (lumen) to " << polyp.tissueHu << " HU (tissue), 10-90% over " << std::setprecision(2)
              << polyp.wallBlurMm << " mm: the polyp's edge ramp is " << polyp.edgeWidthMm << " mm\n";

    const double arcMm = centreline.is_null() ? 0.0 : arcLengthMm(centreline, polyp.truth.baseMm);
    const nlohmann::json entry = polypJson(polyp, arcMm);
    volumes::writeNrrd(volume, options.outPath, options.force);
    writeTextFile(truthPath, truthJson(options, volume, centreline, entry).dump(2) + "\n");
    if (!options.jsonPath.empty()) {
        nlohmann::json summary = {{"volume", fs::absolute(options.outPath).string()},
                                  {"truth", fs::absolute(truthPath).string()},
                                  {"polyp", entry},
                                  {"air_hu", polyp.airHu},
                                  {"wall_10_90_mm", polyp.wallBlurMm},
                                  {"voxels_changed", polyp.voxelsChanged}};
        writeTextFile(options.jsonPath, summary.dump(2) + "\n");
    }
    const glm::dvec3& base = polyp.truth.baseMm;
    std::cout << std::fixed << std::setprecision(1) << "inserted a " << options.diameterMm << " mm "
              << entry["kind"].get<std::string>() << " polyp at (" << base.x << ", " << base.y << ", " << base.z
              << ") mm: tissue " << std::setprecision(0) << polyp.tissueHu << std::setprecision(1) << " HU, edge " << polyp.edgeWidthMm << " mm, "
              << polyp.voxelsChanged << " voxels changed; wrote " << options.outPath << " and " << truthPath << '\n';
}

}  // namespace

void addInsertPolypCommand(CLI::App& program) {
    auto options = std::make_shared<InsertPolypOptions>();
    CLI::App* command = program.add_subcommand(
        "insert-polyp",
        "Insert a synthetic polyp on the colon wall nearest a point of the lumen; write the volume and its ground truth");
    addVolumeOptions(*command, options->volumePath, options->rawSpec);
    command->add_option("--at", options->atMm, "A point in the lumen, x,y,z in volume mm: the polyp goes on the nearest wall")
        ->expected(3)
        ->delimiter(',')
        ->required();
    command->add_option("--diameter", options->diameterMm, "Polyp diameter in mm (3..30; the head's, with --stalk)")
        ->required();
    command->add_option("--stalk", options->stalkLengthMm,
                        "Stalk length in mm, wall to the head: a pedunculated polyp (default 0: sessile)");
    addOutputOptions(*command, options->outPath, "Output volume (.nrrd)", true, options->jsonPath,
                     "Also write a summary of the insertion to this file", options->force, "Replace existing output files");
    command->add_option("--truth", options->truthPath, "Ground-truth JSON (default: the output path with .json)");
    command->add_option("--centreline", options->centrelinePath,
                        "A colon.json (`cvc colon`) or ground truth: its centreline goes into the truth (usable as "
                        "`render --path`), its polyps are kept before the new one");
    command->callback([options] { runInsertPolyp(*options); });
}

}  // namespace app
