/// @brief `cvc bake`: compute the conformal map (or the linear baseline) of a CAVE and write it
/// as a cube map the ray caster samples; bakes are cached by the hash of their inputs.
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

namespace app {
namespace {

struct BakeOptions {
    std::string outPath;
    int size = 1024;
    std::vector<double> boxSize = {2.95, 2.21, 2.95};  // the Immersive Cabin
    std::vector<double> centre = {0.0, 0.0, 0.0};
    std::string map = "conformal";
    std::string metric = "vertex-scaling";
    int meshResolution = conformal::SphereMeshSettings{}.resolution;
    bool useCache = true;
    bool force = false;
};

void runBake(const BakeOptions& options) {
    requireWritableOutput(options.outPath, options.force);
    conformal::BakeSettings settings;
    settings.size = options.size;
    settings.box.size = vec3From(options.boxSize, "--box");
    settings.box.mapCentre = vec3From(options.centre, "--centre");
    settings.kind = conformal::mapKindFromName(options.map);
    settings.mesh.resolution = options.meshResolution;
    settings.flow.metric = options.metric == "circle-packing" ? conformal::DiscreteMetric::CirclePacking
                                                              : conformal::DiscreteMetric::VertexScaling;
    conformal::validateCaveBox(settings.box);

    const auto start = std::chrono::steady_clock::now();
    conformal::BakeReport report;
    const conformal::CubeMap cube =
        options.useCache ? conformal::cachedCubeMap(settings, &report) : conformal::bakeCubeMap(settings, &report);
    conformal::saveCubeMap(cube, options.outPath);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    std::cout << "wrote " << conformal::mapKindName(settings.kind) << " cube map " << cube.size << "^2 x 6 for box "
              << settings.box.size.x << " x " << settings.box.size.y << " x " << settings.box.size.z << " m to "
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
    command->add_option("--box", options->boxSize, "Box width (x), height (y), depth (z) in metres; the ceiling is missing")
        ->expected(3)
        ->capture_default_str();
    command->add_option("--centre", options->centre, "Map centre in CAVE space (metres from the box centre)")
        ->expected(3)
        ->capture_default_str();
    command->add_option("--map", options->map, "conformal (angle-preserving) or linear (the non-conformal baseline)")
        ->check(CLI::IsMember({"conformal", "linear"}))
        ->capture_default_str();
    command->add_option("--metric", options->metric, "Discrete conformal metric of the Ricci flow")
        ->check(CLI::IsMember({"vertex-scaling", "circle-packing"}))
        ->capture_default_str();
    command->add_option("--mesh-resolution", options->meshResolution,
                        "Sphere-mesh grid segments along the longest box edge")
        ->check(CLI::Range(8, 1024))
        ->capture_default_str();
    command->add_flag("!--no-cache", options->useCache, "Always recompute (the result is not stored in the cache)");
    command->add_flag("--force", options->force, "Replace an existing output file");
    command->callback([options] { runBake(*options); });
}

}  // namespace app
