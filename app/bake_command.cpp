/// @brief `cvc bake`: compute the conformal map (or the linear baseline) of a display's CAVE and
/// write it as a cube map the ray caster samples (`cvc render --cube-map`); bakes are cached by
/// the hash of their inputs.
#include <chrono>
#include <iomanip>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "app/commands.h"
#include "app/option_parsing.h"
#include "conformal/cube_map_baker.h"
#include "engine/display/display_json.h"
#include "engine/display/display_map.h"

namespace app {
namespace {

struct BakeOptions {
    std::string outPath;
    int size = 1024;
    std::string display;          // empty: ic5, or a custom CAVE described by --box
    std::vector<double> boxSize;  // empty: the display's
    std::vector<double> centre;   // empty: the display's
    std::string map;              // empty: the display's
    std::string metric = "vertex-scaling";
    int meshResolution = conformal::SphereMeshSettings{}.resolution;
    bool useCache = true;
    bool force = false;
};

void runBake(const BakeOptions& options) {
    requireWritableOutput(options.outPath, options.force);
    // The display says which box, centre and map; the options override them for a CAVE that has
    // no display file. A --box alone describes such a CAVE, named so in the messages.
    engine::Display display = engine::loadDisplay(options.display.empty() ? "ic5" : options.display);
    if (options.display.empty() && !options.boxSize.empty()) display.name = "custom";
    if (!options.boxSize.empty()) display.boxSizeM = vec3From(options.boxSize, "--box");
    if (!options.centre.empty()) display.mapCentreM = vec3From(options.centre, "--centre");
    if (!options.map.empty()) display.map = conformal::mapKindFromName(options.map);
    conformal::BakeSettings settings = engine::bakeSettingsFor(display, options.size);
    settings.mesh.resolution = options.meshResolution;
    settings.flow.metric = options.metric == "circle-packing" ? conformal::DiscreteMetric::CirclePacking
                                                              : conformal::DiscreteMetric::VertexScaling;

    const auto start = std::chrono::steady_clock::now();
    conformal::BakeReport report;
    const conformal::CubeMap cube =
        options.useCache ? conformal::cachedCubeMap(settings, &report) : conformal::bakeCubeMap(settings, &report);
    conformal::saveCubeMap(cube, options.outPath);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    const glm::dvec3 box = settings.box.size;
    const glm::dvec3 centre = settings.box.mapCentre;
    std::cout << "wrote " << conformal::mapKindName(settings.kind) << " cube map " << cube.size
              << "^2 x 6 for display '" << display.name << "', box " << box.x << " x " << box.y << " x " << box.z
              << " m, lacking " << conformal::boxFaceNames(settings.box.missingFaces) << ", map centre ("
              << centre.x << ", " << centre.y << ", " << centre.z << ") m, to "
              << options.outPath << " (input hash " << std::hex << std::setw(16) << std::setfill('0')
              << cube.inputHash << std::dec << std::setfill(' ') << "; ";
    if (report.wasLoadedFromCache) {
        std::cout << "loaded from cache " << report.cachePath.string() << " in " << report.bakeSeconds << " s";
    } else {
        std::cout << "map " << report.mapSeconds << " s, bake " << report.bakeSeconds << " s";
    }
    std::cout << "; total " << seconds << " s)\n";
}

}  // namespace

void addBakeCommand(CLI::App& program) {
    auto options = std::make_shared<BakeOptions>();
    CLI::App* command = program.add_subcommand(
        "bake", "Bake the display-to-scene direction map of a CAVE into a float32 RGBA cube map (Vulkan face order)");
    command->add_option("-o,--out", options->outPath, "Output cube-map file")->required();
    command->add_option("--size", options->size, "Texels along each face's edge")
        ->check(CLI::Range(2, 8192))
        ->capture_default_str();
    command->add_option("--display", options->display,
                        "A preset (ic5, cave4) or a display JSON file: its box, map centre, missing walls and map "
                        "are baked (default: ic5; a display with all six walls has no map to bake)");
    command->add_option("--box", options->boxSize,
                        "Override the display's box: width (x), height (y), depth (z) in metres (without "
                        "--display: a custom CAVE lacking its ceiling)")
        ->expected(3);
    command->add_option("--centre", options->centre,
                        "Override the display's map centre in CAVE space (metres from the box centre)")
        ->expected(3);
    command->add_option("--map", options->map,
                        "Override the display's map: conformal (angle-preserving) or linear (the non-conformal "
                        "baseline)")
        ->check(CLI::IsMember({"conformal", "linear"}));
    command->add_option("--metric", options->metric, "Discrete conformal metric of the Ricci flow")
        ->check(CLI::IsMember({"vertex-scaling", "circle-packing"}))
        ->capture_default_str();
    command->add_option("--mesh-resolution", options->meshResolution,
                        "Sphere-mesh grid segments along the longest box edge")
        ->check(CLI::Range(8, 1024))
        ->capture_default_str();
    command->add_flag("!--no-cache", options->useCache, "Always recompute (the result is not stored in the cache)");
    command->add_flag("--force", options->force, "Replace an existing output file");
    command->callback([options, command] {
        const conformal::MapKind map = !options->map.empty() ? conformal::mapKindFromName(options->map)
                                       : engine::loadDisplay(options->display.empty() ? "ic5" : options->display).map;
        if (map != conformal::MapKind::Conformal) {
            refuseGivenOptions(*command, {"--metric", "--mesh-resolution"},
                               "shapes the Ricci flow of the conformal map; the " + conformal::mapKindName(map) +
                                   " map has none");
        }
        runBake(*options);
    });
}

}  // namespace app
