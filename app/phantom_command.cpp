/// @brief `cvc phantom`: write a synthetic volume whose surfaces are known in closed form.
#include <iostream>
#include <memory>

#include <CLI/CLI.hpp>

#include "app/commands.h"
#include "app/option_parsing.h"
#include "volumes/analytic_phantom.h"
#include "volumes/nrrd_io.h"

namespace app {
namespace {

struct PhantomOptions {
    std::string kind = "ball";
    std::string outPath = "phantom.nrrd";
    int size = 128;
    double spacingMm = 1.0;
    bool force = false;
};

void runPhantom(const PhantomOptions& options) {
    requireWritableOutput(options.outPath, options.force);
    volumes::GridSpec grid{{options.size, options.size, options.size}, glm::dvec3(options.spacingMm)};
    const double centreMm = 0.5 * (options.size - 1) * options.spacingMm;
    const double extentMm = options.size * options.spacingMm;
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
    volumes::writeNrrd(volume, options.outPath, options.force);
    std::cout << "wrote " << options.kind << " phantom " << options.size << "^3 at " << options.spacingMm
              << " mm to " << options.outPath << '\n';
}

}  // namespace

void addPhantomCommand(CLI::App& program) {
    auto options = std::make_shared<PhantomOptions>();
    CLI::App* command = program.add_subcommand("phantom", "Write a synthetic phantom volume");
    command->add_option("--kind", options->kind, "ball (a solid ball) or tube (an air-filled tube)")
        ->check(CLI::IsMember({"ball", "tube"}))
        ->capture_default_str();
    command->add_option("-o,--out", options->outPath, "Output NRRD file")->capture_default_str();
    command->add_option("--size", options->size, "Voxels along each axis")
        ->check(CLI::Range(8, 1024))
        ->capture_default_str();
    command->add_option("--spacing", options->spacingMm, "Voxel spacing in mm")
        ->check(CLI::Range(0.01, 10.0))
        ->capture_default_str();
    command->add_flag("--force", options->force, "Replace an existing output file");
    command->callback([options] { runPhantom(*options); });
}

}  // namespace app
