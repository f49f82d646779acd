/// @brief `cvc colon`: find the air-filled colon of a CT, cleanse tagged fluid, extract the
/// centreline per segment and write what a fly-through needs (colon/colon_analysis.h).
#include "app/colon_command.h"

#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "app/option_groups.h"
#include "app/option_parsing.h"
#include "colon/colon_report.h"
#include "colon/overview_image.h"
#include "colon/slicer_files.h"
#include "engine/output/png_writer.h"
#include "volumes/load_volume.h"
#include "volumes/nrrd_io.h"

namespace app {
namespace {

namespace fs = std::filesystem;

ColonOutputs outputsIn(const std::string& folder) {
    const fs::path dir(folder);
    return {(dir / "colon.json").string(), (dir / "centreline.txt").string(), (dir / "lumen.nrrd").string(),
            (dir / "overview.png").string(), (dir / "cleansed.nrrd").string(), (dir / "lumen.seg.nrrd").string(),
            {}, false};
}

/// Segment N's centreline for 3D Slicer.
std::string centrelineMarkupsIn(const std::string& folder, std::size_t segmentIndex) {
    return (fs::path(folder) / ("centreline_segment_" + std::to_string(segmentIndex + 1) + ".mrk.json")).string();
}

/// Writes the lumen and the centreline for 3D Slicer (colon/slicer_files.h); with `overwrite`,
/// removes the curves of segments an earlier analysis of the folder had and this one has not.
void writeSlicerFiles(const colon::ColonAnalysis& analysis, const volumes::Volume& volume, const std::string& folder,
                      bool overwrite, ColonOutputs& outputs) {
    colon::writeLumenSegmentation(analysis, outputs.lumenSegmentation, overwrite);
    for (std::size_t s = 0; s < analysis.segments.size(); ++s) {
        outputs.centrelineMarkups.push_back(centrelineMarkupsIn(folder, s));
        requireWritableOutput(outputs.centrelineMarkups.back(), overwrite);
        writeTextFile(outputs.centrelineMarkups.back(), colon::centrelineMarkupsJson(analysis, s, volume));
    }
    for (std::size_t s = analysis.segments.size(); overwrite && fs::exists(centrelineMarkupsIn(folder, s)); ++s) {
        fs::remove(centrelineMarkupsIn(folder, s));
    }
}

/// A finished analysis of the same volume in `outputs`' folder, if there is one.
bool isReusable(const ColonOutputs& outputs, const std::string& volumePath) {
    std::ifstream in(outputs.colonJson);
    if (!in) return false;
    try {
        const nlohmann::json doc = nlohmann::json::parse(in);
        return doc.value("volume", std::string{}) == fs::absolute(volumePath).string() && fs::exists(outputs.overviewPng);
    } catch (const nlohmann::json::exception&) {
        return false;
    }
}

void printSummary(const colon::ColonAnalysis& analysis, const ColonOutputs& outputs) {
    std::cout << std::fixed << std::setprecision(1);
    std::cout << "colon: " << analysis.segments.size() << " segment(s), rectum -> caecum:\n";
    for (std::size_t s = 0; s < analysis.segments.size(); ++s) {
        const auto& segment = analysis.segments[s];
        std::cout << "  segment " << s + 1 << ": " << segment.centreline.lengthMm << " mm, " << segment.volumeMl
                  << " mL, lumen radius " << segment.centreline.meanRadiusMm << " mm mean\n";
        if (s < analysis.gapsMm.size()) std::cout << "  gap: " << analysis.gapsMm[s] << " mm\n";
    }
    if (analysis.isCleansed) {
        std::cout << "cleansed " << analysis.cleansing.pools << " pool(s) of tagged fluid, " << analysis.cleansing.fluidMl
                  << " mL (" << outputs.cleansedNrrd << ")\n";
    } else {
        std::cout << "no tagged fluid cleansed\n";
    }
    std::cout << "analysed in " << analysis.seconds << " s\nwrote " << fs::path(outputs.colonJson).parent_path().string()
              << '\n';
}

}  // namespace

ColonOutputs runColonAnalysis(const ColonRequest& request) {
    ColonOutputs outputs = outputsIn(request.outFolder);
    if (request.resume && isReusable(outputs, request.volumePath)) {
        outputs.wasReused = true;
        if (!fs::exists(outputs.cleansedNrrd)) outputs.cleansedNrrd.clear();
        std::cerr << "colon: reusing the analysis in " << request.outFolder << '\n';
        return outputs;
    }
    fs::create_directories(request.outFolder);
    for (const std::string& path : {outputs.colonJson, outputs.centrelineText, outputs.lumenNrrd, outputs.overviewPng,
                                    outputs.lumenSegmentation}) {
        requireWritableOutput(path, request.force || request.resume);
    }
    if (!request.jsonPath.empty()) requireWritableOutput(request.jsonPath, request.force);
    if (fs::exists(outputs.cleansedNrrd) && !(request.force || request.resume)) {
        throw std::invalid_argument(outputs.cleansedNrrd + " exists (use --force to replace it)");
    }

    volumes::LoadOptions load;
    if (!request.rawSpec.empty()) load.raw = volumes::parseRawSpec(request.rawSpec);
    std::cerr << "colon: loading " << request.volumePath << '\n';
    volumes::Volume volume = volumes::loadVolume(request.volumePath, load);
    const auto progress = [](const std::string& step, int done, int total) {
        std::cerr << "colon: [" << done << '/' << total << "] " << step << '\n';
    };
    const colon::ColonAnalysis analysis = colon::analyseColon(volume, request.settings, progress);

    const bool overwrite = request.force || request.resume;
    volumes::writeNrrd(analysis.labels, outputs.lumenNrrd, overwrite);
    if (analysis.isCleansed) {
        volumes::writeNrrd(volume, outputs.cleansedNrrd, overwrite);
    } else {
        if (overwrite && fs::exists(outputs.cleansedNrrd)) fs::remove(outputs.cleansedNrrd);  // stale from an earlier run
        outputs.cleansedNrrd.clear();
    }
    writeTextFile(outputs.centrelineText, colon::centrelineText(analysis));
    writeSlicerFiles(analysis, volume, request.outFolder, overwrite, outputs);
    const std::string json = colon::colonJson(analysis, volume, fs::absolute(request.volumePath).string());
    const colon::RgbaImage overview = colon::overviewImage(volume, analysis);  // the scan as rendered: cleansed
    engine::writePng(outputs.overviewPng, overview.width, overview.height, overview.rgba, true);
    writeTextFile(outputs.colonJson, json);  // last: its presence marks a finished analysis
    if (!request.jsonPath.empty()) writeTextFile(request.jsonPath, json);
    printSummary(analysis, outputs);
    return outputs;
}

void addColonCommand(CLI::App& program) {
    auto request = std::make_shared<ColonRequest>();
    auto cleanse = std::make_shared<std::string>("auto");
    CLI::App* command = program.add_subcommand(
        "colon", "Find the air-filled colon of a CT, cleanse tagged fluid, extract its centreline (rectum -> caecum)");
    addVolumeOptions(*command, request->volumePath, request->rawSpec);
    addOutputOptions(*command, request->outFolder, "Output folder", true, request->jsonPath,
                     "Also write the summary (colon.json's content) to this file", request->force,
                     "Replace existing output files");
    command->add_option("--air-threshold", request->settings.segmentation.airThresholdHu, "Air is below this HU")
        ->check(CLI::Range(-1024.0, 0.0))
        ->capture_default_str();
    command->add_option("--cleanse", *cleanse, "auto: cleanse tagged fluid where found; off: never")
        ->check(CLI::IsMember({"auto", "off"}))
        ->capture_default_str();
    command->add_option("--smoothing", request->settings.centreline.smoothingMm,
                        "Centreline smoothing, Gaussian sigma along the path in mm")
        ->check(CLI::Range(0.0, 50.0))
        ->capture_default_str();
    command->add_option("--min-length", request->settings.minPathLengthMm,
                        "Lumen segments with a shorter centreline are reported but not flown through (mm)")
        ->check(CLI::Range(0.0, 10000.0))
        ->capture_default_str();
    command->callback([request, cleanse] {
        request->settings.cleansing = *cleanse == "off" ? colon::Cleansing::Off : colon::Cleansing::Auto;
        runColonAnalysis(*request);
    });
}

}  // namespace app
