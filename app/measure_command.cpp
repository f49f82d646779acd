/// @brief `cvc measure`: distances in millimetres on a rendered wall, read from its hit image
/// (`cvc render --hits`): between two pixels, or the largest diameter of the polyp-like patch
/// around one pixel (colon/surface_measure.h).
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "app/option_parsing.h"
#include "colon/hit_image.h"
#include "colon/surface_measure.h"

namespace app {
namespace {

namespace fs = std::filesystem;

struct MeasureOptions {
    std::string hitsPath;
    std::string from, to, polypDiameter;
    std::string jsonPath;
    bool force = false;
};

/// "X,Y" (whole pixel numbers) -> {X, Y}; `option` names it in the error.
std::array<int, 2> parsePixel(const std::string& text, const std::string& option) {
    std::istringstream in(text);
    long long x = 0, y = 0;
    char comma = 0;
    if (!(in >> x >> comma >> y) || comma != ',' || !(in >> std::ws).eof() || x < 0 || y < 0 || x > (1 << 20) ||
        y > (1 << 20)) {
        throw std::invalid_argument(option + " \"" + text + "\": expected a pixel X,Y (column, row from the top)");
    }
    return {static_cast<int>(x), static_cast<int>(y)};
}

nlohmann::json vec(const glm::dvec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); }

std::string mm(const glm::dvec3& v) {
    std::ostringstream out;
    out << std::fixed << std::setprecision(2) << "(" << v.x << ", " << v.y << ", " << v.z << ") mm";
    return out.str();
}

std::string pixel(const std::array<int, 2>& p) {
    return "(" + std::to_string(p[0]) + "," + std::to_string(p[1]) + ")";
}

void runMeasure(const MeasureOptions& options) {
    const bool twoPixels = !options.from.empty() || !options.to.empty();
    const bool diameter = !options.polypDiameter.empty();
    if (twoPixels == diameter) {
        throw std::invalid_argument(
            "give either --from X,Y --to X,Y (a distance) or --polyp-diameter X,Y (a patch's diameter), not " +
            std::string(diameter ? "both" : "neither"));
    }
    if (twoPixels && (options.from.empty() || options.to.empty())) {
        throw std::invalid_argument("--from and --to go together: give both");
    }
    if (!options.jsonPath.empty()) requireWritableOutput(options.jsonPath, options.force);
    const colon::HitImage image = colon::readHitImage(options.hitsPath);

    nlohmann::json summary = {{"hits", fs::absolute(options.hitsPath).string()},
                              {"width", image.width},
                              {"height", image.height}};
    std::ostringstream line;
    line << std::fixed << std::setprecision(2);
    if (twoPixels) {
        const auto a = parsePixel(options.from, "--from");
        const auto b = parsePixel(options.to, "--to");
        const double distance = colon::surfaceDistanceMm(image, a[0], a[1], b[0], b[1]);
        const glm::dvec3& pa = image.hitMm[image.index(a[0], a[1])];
        const glm::dvec3& pb = image.hitMm[image.index(b[0], b[1])];
        line << "distance: " << distance << " mm between " << pixel(a) << " at " << mm(pa) << " and " << pixel(b)
             << " at " << mm(pb);
        summary["mode"] = "distance";
        summary["distance_mm"] = distance;
        summary["from"] = {{"pixel", a}, {"hit_mm", vec(pa)}};
        summary["to"] = {{"pixel", b}, {"hit_mm", vec(pb)}};
    } else {
        const auto seed = parsePixel(options.polypDiameter, "--polyp-diameter");
        const colon::PatchDiameter patch = colon::polypDiameter(image, seed[0], seed[1]);
        line << "polyp diameter: " << patch.diameterMm << " mm between " << pixel(patch.end0) << " at "
             << mm(patch.end0Mm) << " and " << pixel(patch.end1) << " at " << mm(patch.end1Mm) << " (patch of "
             << patch.pixelCount << " pixels around " << pixel(seed) << ", footprint " << std::setprecision(3)
             << patch.footprintMm << " mm/pixel)";
        summary["mode"] = "polyp_diameter";
        summary["seed"] = {{"pixel", seed}, {"hit_mm", vec(image.hitMm[image.index(seed[0], seed[1])])}};
        summary["diameter_mm"] = patch.diameterMm;
        summary["pixel_count"] = patch.pixelCount;
        summary["ends"] = nlohmann::json::array({{{"pixel", patch.end0}, {"hit_mm", vec(patch.end0Mm)}},
                                                 {{"pixel", patch.end1}, {"hit_mm", vec(patch.end1Mm)}}});
        summary["footprint_mm"] = patch.footprintMm;
        if (patch.sphereRadiusMm > 0.0) {
            summary["fitted_sphere"] = {{"centre_mm", vec(patch.sphereCentreMm)}, {"radius_mm", patch.sphereRadiusMm}};
        }
    }
    if (!options.jsonPath.empty()) writeTextFile(options.jsonPath, summary.dump(2) + "\n");
    std::cout << line.str() << '\n';
}

}  // namespace

void addMeasureCommand(CLI::App& program) {
    auto options = std::make_shared<MeasureOptions>();
    CLI::App* command = program.add_subcommand(
        "measure", "Measure in mm on a rendered wall from its hit image (`cvc render --hits`): a distance between "
                   "two pixels, or a polyp's diameter around one");
    command->add_option("hits,--hits", options->hitsPath, "Hit image (.nrrd) written by `cvc render --hits`")
        ->required();
    command->add_option("--from", options->from, "Distance mode: first pixel X,Y (column, row from the top)");
    command->add_option("--to", options->to, "Distance mode: second pixel X,Y");
    command->add_option("--polyp-diameter", options->polypDiameter,
                        "Diameter mode: a pixel X,Y on the polyp; the largest diameter of its protruding patch");
    command->add_option("--json", options->jsonPath, "Also write a machine-readable summary to this file");
    command->add_flag("--force", options->force, "Replace an existing --json file");
    command->callback([options] { runMeasure(*options); });
}

}  // namespace app
