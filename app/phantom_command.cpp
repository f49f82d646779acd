/// @brief `cvc phantom`: write a synthetic volume whose geometry is known: a colon with folds
/// and polyps (plus its ground-truth JSON), or the analytic ball and tube of the renderer tests.
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>

#include <CLI/CLI.hpp>

#include "app/commands.h"
#include "app/option_parsing.h"
#include "volumes/analytic_phantom.h"
#include "volumes/colon_phantom.h"
#include "volumes/nrrd_io.h"
#include "volumes/vdb_io.h"

namespace app {
namespace {

struct PhantomOptions {
    std::string kind = "colon";
    std::string outPath = "phantom.nrrd";
    std::string truthPath;   // colon only; default: the output path with .json
    int size = 0;            // 0: the kind's default (colon 256, ball and tube 128)
    double spacingMm = 0.0;  // 0: the kind's default (colon 0.6 mm, ball and tube 1 mm)
    std::vector<std::string> polyps;
    int randomPolyps = 0;  // > 0: that many random polyps instead of the listed or default ones
    double noiseSigmaHu = 15.0;
    std::uint64_t seed = 1;
    // Anatomy around the colon (colon only), for segmentation and centreline tests.
    std::uint64_t shapeSeed = 0;
    bool body = false;
    bool lung = false;
    std::vector<std::string> collapses;
    std::vector<std::string> fluidPools;
    bool anatomy = false;
    bool force = false;
};

bool isVdbPath(const std::string& path) {
    return std::filesystem::path(path).extension() == ".vdb";
}

void writeVolume(const volumes::Volume& volume, const std::string& path, bool force) {
    if (isVdbPath(path)) {
        volumes::writeVdb(volume, path, force);
    } else {
        volumes::writeNrrd(volume, path, force);
    }
}

/// --anatomy first (body, lungs, its collapse and pool), then the single options on top:
/// --collapse and --fluid replace the anatomy's defaults, as --polyp replaces the default polyps.
void applyAnatomyOptions(const PhantomOptions& options, volumes::ColonPhantomSpec& spec) {
    if (options.anatomy) spec = volumes::ColonPhantomSpec::withAnatomy(spec);
    spec.shapeSeed = options.shapeSeed;
    spec.hasBody = spec.hasBody || options.body;
    spec.hasLung = spec.hasLung || options.lung;
    if (!options.collapses.empty()) {
        spec.collapses.clear();
        for (const std::string& text : options.collapses) spec.collapses.push_back(volumes::parseCollapseSpec(text));
    }
    if (!options.fluidPools.empty()) {
        spec.fluidPools.clear();
        for (const std::string& text : options.fluidPools)
            spec.fluidPools.push_back(volumes::parseFluidPoolSpec(text));
    }
}

void runColon(const PhantomOptions& options) {
    const std::string truthPath = options.truthPath.empty()
                                      ? std::filesystem::path(options.outPath).replace_extension(".json").string()
                                      : options.truthPath;
    requireWritableOutput(truthPath, options.force);
    volumes::ColonPhantomSpec spec;
    const int size = options.size > 0 ? options.size : 256;
    spec.grid = {{size, size, size}, glm::dvec3(options.spacingMm > 0.0 ? options.spacingMm : 0.6)};
    spec.noiseSigmaHu = options.noiseSigmaHu;
    spec.seed = options.seed;
    if (!options.polyps.empty()) {
        spec.polyps.clear();
        for (const std::string& text : options.polyps) spec.polyps.push_back(volumes::parsePolypSpec(text));
    }
    if (options.randomPolyps != 0) {
        spec.polyps.clear();
        spec.randomPolypCount = options.randomPolyps;
    }
    applyAnatomyOptions(options, spec);
    const auto start = std::chrono::steady_clock::now();
    const volumes::ColonPhantom phantom = volumes::makeColonPhantom(spec);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    writeVolume(phantom.volume, options.outPath, options.force);
    std::ofstream truth(truthPath, std::ios::trunc);
    truth << volumes::colonTruthJson(spec, phantom);
    if (!truth) throw volumes::VolumeError(truthPath + ": write failed");
    const auto onFolds = std::count_if(phantom.polyps.begin(), phantom.polyps.end(),
                                       [](const volumes::PolypTruth& p) { return p.isOnFold; });
    std::cout << "wrote colon phantom " << size << "^3 at " << spec.grid.spacingMm.x << " mm with "
              << phantom.polyps.size() << " polyps"
              << (onFolds > 0 ? " (" + std::to_string(onFolds) + " on folds)" : "")
              << " and " << phantom.foldArcLengthsMm.size() << " folds to "
              << options.outPath << " (ground truth " << truthPath << "; built in " << seconds << " s)\n";
}

void runPhantom(const PhantomOptions& options) {
    requireWritableOutput(options.outPath, options.force);
    if (options.kind == "colon") {
        runColon(options);
        return;
    }
    const int size = options.size > 0 ? options.size : 128;
    const double spacingMm = options.spacingMm > 0.0 ? options.spacingMm : 1.0;
    volumes::GridSpec grid{{size, size, size}, glm::dvec3(spacingMm)};
    const double centreMm = 0.5 * (size - 1) * spacingMm;
    const double extentMm = size * spacingMm;
    volumes::Volume volume;
    if (options.kind == "ball") {
        volumes::BallSpec spec;
        spec.grid = grid;
        spec.centreMm = glm::dvec3(centreMm);
        spec.radiusMm = 0.3 * extentMm;
        volume = volumes::makeBallPhantom(spec);
    } else {
        volumes::TubeSpec spec;
        spec.grid = grid;
        spec.axisMm = glm::dvec2(centreMm);
        spec.radiusMm = 0.25 * extentMm;
        volume = volumes::makeTubePhantom(spec);
    }
    writeVolume(volume, options.outPath, options.force);
    std::cout << "wrote " << options.kind << " phantom " << size << "^3 at " << spacingMm << " mm to "
              << options.outPath << '\n';
}

}  // namespace

void addPhantomCommand(CLI::App& program) {
    auto options = std::make_shared<PhantomOptions>();
    CLI::App* command = program.add_subcommand(
        "phantom",
        "Write a synthetic phantom volume (.nrrd, or .vdb by extension); colon also writes its ground truth as JSON");
    command
        ->add_option(
            "--kind", options->kind,
            "colon (curved tube with folds and polyps), ball (a solid ball) or tube (an air-filled straight tube)")
        ->check(CLI::IsMember({"colon", "ball", "tube"}))
        ->capture_default_str();
    command->add_option("-o,--out", options->outPath, "Output volume (.nrrd or .vdb)")->capture_default_str();
    command->add_option("--truth", options->truthPath, "Colon ground-truth JSON (default: the output path with .json)");
    command->add_option("--size", options->size, "Voxels along each axis (default: colon 256, ball and tube 128)")
        ->check(CLI::Range(8, 1024));
    command->add_option("--spacing", options->spacingMm, "Voxel spacing in mm (default: colon 0.6, ball and tube 1)")
        ->check(CLI::Range(0.01, 10.0));
    command->add_option("--polyp", options->polyps,
                        "Colon polyp KIND:DIAMETER_MM:POSITION:ANGLE_DEG[:STALK_MM], KIND sessile, pedunculated or "
                        "flat, POSITION 0..1 along the colon; repeat for several (default: five polyps of 3 to 12 mm)");
    command->add_option("--random-polyps", options->randomPolyps,
                        "Colon: N (1.." + std::to_string(volumes::kMaxRandomPolyps) +
                            ") polyps of 5 to 15 mm laid out at random from --seed instead of the default ones: "
                            "sessile, pedunculated and flat, about a quarter on a fold's ridge");
    command->add_option("--noise", options->noiseSigmaHu, "Colon CT noise, standard deviation in HU")
        ->check(CLI::Range(0.0, 200.0))
        ->capture_default_str();
    command->add_option("--seed", options->seed, "Colon noise seed (and the layout of --random-polyps)")
        ->capture_default_str();
    command->add_option("--shape-seed", options->shapeSeed,
                        "Colon shape: 0 the standard curve, N > 0 its control points moved by up to 5% of the grid")
        ->capture_default_str();
    command->add_flag("--body", options->body, "Colon: an elliptic body outline with air outside it");
    command->add_flag("--lung", options->lung, "Colon: two lung bases (-860 HU) at the top of the grid");
    command->add_option("--collapse", options->collapses,
                        "Colon: a collapsed stretch POSITION[:LENGTH_MM] (default 12 mm) with no air, splitting "
                        "the lumen; repeat for several");
    command->add_option("--fluid", options->fluidPools,
                        "Colon: tagged fluid (+600 HU) POSITION[:LENGTH_MM[:DEPTH_MM]] (default 40 mm, 6 mm deep) "
                        "in the lumen's lowest part; repeat for several");
    command->add_flag("--anatomy", options->anatomy,
                      "Colon: --body --lung --collapse 0.42:12 --fluid 0.238:40:6 (--collapse and --fluid "
                      "replace these defaults)");
    command->add_flag("--force", options->force, "Replace existing output files");
    command->callback([options, command] {
        if (options->kind != "colon") {
            refuseGivenOptions(*command,
                               {"--truth", "--polyp", "--random-polyps", "--noise", "--seed", "--shape-seed", "--body",
                                "--lung", "--collapse", "--fluid", "--anatomy"},
                               "describes the colon phantom; a " + options->kind + " phantom has no such part");
        }
        if (command->count("--random-polyps") > 0) {
            if (options->randomPolyps < 1 || options->randomPolyps > volumes::kMaxRandomPolyps) {
                throw std::invalid_argument("--random-polyps " + std::to_string(options->randomPolyps) +
                                            ": 1.." + std::to_string(volumes::kMaxRandomPolyps) +
                                            " polyps fit in the colon phantom");
            }
            refuseGivenOptions(*command, {"--polyp"},
                               "cannot go with --random-polyps, which lays out the polyps itself");
        }
        runPhantom(*options);
    });
}

}  // namespace app
