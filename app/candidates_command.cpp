/// @brief `cvc candidates`: polyp candidates on the colon wall, ranked, each placed on the path
/// of the fly-through (the nearest frame and the arc length), with a picture of the first ones
/// (engine/studies/candidate_study.h, colon/polyp_candidates.h). No Vulkan.
#include <iomanip>
#include <iostream>
#include <memory>

#include <CLI/CLI.hpp>

#include "app/commands.h"
#include "app/option_groups.h"
#include "app/option_parsing.h"
#include "engine/studies/candidate_study.h"

namespace app {
namespace {

struct CandidatesOptions {
    engine::CandidateStudySettings study;
    std::string jsonPath;
};

void printSummary(const engine::CandidateStudyResult& result, const std::string& folder) {
    const auto& search = result.search;
    std::cout << std::fixed << std::setprecision(1);
    std::cout << "candidates: " << search.candidates.size() << " on " << search.wallAreaMm2 / 100.0
              << " cm^2 of colon wall (" << search.capRegions << " cap regions; dropped: " << search.droppedSmall
              << " small, " << search.droppedElongated << " elongated, " << search.droppedUnmeasured
              << " unmeasured or under the minimum diameter, " << search.droppedBeyondLimit << " past the limit)\n";
    for (std::size_t r = 0; r < search.candidates.size() && r < 10; ++r) {
        const auto& c = search.candidates[r];
        std::cout << "  " << r + 1 << ": " << c.diameterMm << " mm at (" << c.centreMm.x << ", " << c.centreMm.y << ", "
                  << c.centreMm.z << "), score " << std::setprecision(2) << c.score << std::setprecision(1);
        if (result.places[r].nearestFrame >= 0) {
            std::cout << ", frame " << result.places[r].nearestFrame << ", " << result.places[r].arcLengthMm << " mm along the path";
        }
        std::cout << '\n';
    }
    std::cout << "found in " << result.seconds << " s\nwrote " << folder << '\n';
}

}  // namespace

void addCandidatesCommand(CLI::App& program) {
    auto options = std::make_shared<CandidatesOptions>();
    auto& study = options->study;
    CLI::App* command = program.add_subcommand(
        "candidates", "Polyp candidates on the colon wall by its shape (CPU only), ranked and placed along the path");
    addVolumeOptions(*command, study.volumePath, study.rawSpec);
    addOutputOptions(*command, study.outFolder, "Output folder", true, options->jsonPath,
                     "Also write the summary (candidates.json's content) to this file", study.force,
                     "Replace a run's earlier output in the folder");
    command->add_option("--path", study.pathFile,
                        "The fly-through's path: auto (the colon analysis's centreline), a centreline file, or none")
        ->capture_default_str();
    command->add_option("--path-step", study.pathStepMm, "Arc length between the fly-through's frames in mm")
        ->capture_default_str();
    command->add_option("--iso", study.candidates.isoHu, "The wall's iso value (HU), as rendered")
        ->check(CLI::Range(-1024.0, 3071.0))
        ->capture_default_str();
    command->add_option("--min-diameter", study.candidates.minDiameterMm, "Smallest candidate reported (mm)")
        ->check(CLI::Range(0.0, 100.0))
        ->capture_default_str();
    command->add_option("--max-candidates", study.candidates.maxCandidates, "Report at most this many, best first")
        ->check(CLI::Range(1, 10000))
        ->capture_default_str();
    command->add_option("--pictures", study.pictures, "A picture of each of the first this many")
        ->check(CLI::Range(0, 100))
        ->capture_default_str();
    command->callback([options] {
        auto& s = options->study;
        if (s.pathFile == "none") s.pathFile.clear();
        if (!options->jsonPath.empty()) requireWritableOutput(options->jsonPath, s.force);
        const auto result = engine::runCandidateStudy(s, [](const std::string& line) { std::cerr << line << '\n'; });
        if (!options->jsonPath.empty()) writeTextFile(options->jsonPath, result.json);
        printSummary(result, s.outFolder);
    });
}

}  // namespace app
