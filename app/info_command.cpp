/// @brief `cvc info FILE`: what a volume is (format, grid, orientation) and what it holds
/// (HU range, percentiles, a histogram over tissue classes, bricks that empty-space skipping
/// would keep for a typical colon-wall iso value).
#include <cstdio>
#include <iomanip>
#include <iostream>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "app/commands.h"
#include "volumes/dicom_reader.h"
#include "volumes/load_volume.h"
#include "volumes/volume_stats.h"

namespace app {
namespace {

struct InfoOptions {
    std::string path;
    std::string rawSpec;
    std::string seriesUid;
    double isoHu = -500.0;
};

void printVector(std::ostream& out, const glm::dvec3& v) {
    out << '(' << v.x << ", " << v.y << ", " << v.z << ')';
}

void runInfo(const InfoOptions& options) {
    volumes::LoadOptions load;
    if (!options.rawSpec.empty()) load.raw = volumes::parseRawSpec(options.rawSpec);
    load.dicomSeriesUid = options.seriesUid;
    const volumes::LoadedVolume loaded = volumes::loadVolumeWithBricks(options.path, load);
    const volumes::Volume& v = loaded.volume;
    const volumes::VolumeStats stats = volumes::volumeStatsOf(v);

    std::ostream& out = std::cout;
    out << std::setprecision(6);
    out << "file:        " << options.path << '\n'
        << "format:      " << volumes::volumeFormatName(loaded.format) << '\n';
    if (loaded.format == volumes::VolumeFormat::DicomSeries) {
        // Folders often hold scouts or reformats beside the scan: say which series was read.
        const auto series = volumes::listDicomSeries(options.path);
        const std::string& read = options.seriesUid.empty() ? series.front().seriesUid : options.seriesUid;
        out << "series:      " << read << " (" << series.size() << " series in the folder";
        for (const volumes::DicomSeriesInfo& s : series) {
            if (s.seriesUid != read) out << "; also " << s.seriesUid << ", " << s.fileCount << " files";
        }
        out << ")\n";
    }
    out << "dims:        " << v.dims[0] << " x " << v.dims[1] << " x " << v.dims[2] << " voxels (" << v.voxelCount()
        << ")\n"
        << "spacing:     " << v.spacingMm.x << " x " << v.spacingMm.y << " x " << v.spacingMm.z << " mm\n"
        << "extent:      " << v.extentMm().x << " x " << v.extentMm().y << " x " << v.extentMm().z << " mm\n"
        << "origin:      ";
    printVector(out, v.originLps);
    out << " mm (LPS)\n"
        << "orientation: " << volumes::orientationCode(v) << " (axis directions in LPS: ";
    for (int axis = 0; axis < 3; ++axis) {
        printVector(out, v.directionLps[axis]);
        out << (axis < 2 ? " " : ")\n");
    }
    out << "HU range:    " << stats.minHu << " .. " << stats.maxHu << ", mean " << std::fixed << std::setprecision(1)
        << stats.meanHu << '\n'
        << "percentiles: 1% " << stats.percentileHu[0] << ", 50% " << stats.percentileHu[1] << ", 99% "
        << stats.percentileHu[2] << " HU\n"
        << "histogram:\n";
    for (const volumes::HuBin& bin : stats.bins) {
        const double percent = 100.0 * static_cast<double>(bin.count) / static_cast<double>(v.voxelCount());
        const int bar = static_cast<int>(percent / 2.0 + 0.5);
        out << "  " << std::left << std::setw(17) << bin.name << std::right << std::setw(6) << percent << " %  "
            << std::string(static_cast<std::size_t>(bar), '#') << '\n';
    }
    const auto mask = volumes::bricksForIsoValue(loaded.bricks, options.isoHu);
    std::size_t kept = 0;
    for (const uint8_t m : mask) kept += m;
    out << "bricks:      " << loaded.bricks.brickDims[0] << " x " << loaded.bricks.brickDims[1] << " x "
        << loaded.bricks.brickDims[2] << " of 8^3; " << kept << " of " << mask.size() << " ("
        << 100.0 * static_cast<double>(kept) / static_cast<double>(mask.size()) << " %) straddle iso "
        << std::setprecision(0) << options.isoHu << " HU\n";
}

}  // namespace

void addInfoCommand(CLI::App& program) {
    auto options = std::make_shared<InfoOptions>();
    CLI::App* command = program.add_subcommand(
        "info",
        "Print a volume's grid, orientation, HU range and histogram (DICOM folder, .nrrd, .nhdr, .nii, "
        ".nii.gz, .mha, .mhd, .vdb, raw)");
    command->add_option("FILE", options->path, "Volume file, or a folder holding one DICOM series")->required();
    command->add_option("--raw", options->rawSpec,
                        "Describe a headerless raw file: DIMS:TYPE:SPACING[:big][:skip=N], e.g. "
                        "512x512x451:int16:0.7x0.7x1.25");
    command->add_option("--series", options->seriesUid, "DICOM SeriesInstanceUID to read (default: the largest)");
    command->add_option("--iso", options->isoHu, "Iso value (HU) for the brick count")->capture_default_str();
    command->callback([options] { runInfo(*options); });
}

}  // namespace app
