#include "distribution/coverage_over_ranks.h"

#include <chrono>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "colon/slicer_files.h"
#include "distribution/work_share.h"
#include "engine/display/display_map.h"
#include "engine/output/text_file.h"
#include "engine/sequence/frame_sequence.h"

namespace distribution {
namespace {

namespace fs = std::filesystem;

/// Flies this rank's frames of the row's path (every frame for one process; frame i goes to rank
/// i mod N under mpirun), marks what they show and writes each one's sheet; on rank 0, the whole
/// row's coverage merged from every rank's first sightings.
engine::CoverageRowResult flyAndMeasure(MpiSession& session, const engine::CoverageStudySettings& settings,
                                        const engine::CoverageRow& row, const engine::CoverageScene& scene,
                                        engine::Raycaster& raycaster, int mapSize, colon::SurfaceCoverage& coverage,
                                        const fs::path& folder, const CoverageReport& report) {
    engine::CoverageRowResult result;
    result.job = engine::coverageJobOf(settings, row, scene);
    // Rank 0 bakes or finds the map first; the others then load it from the cache it filled.
    if (row.display.map != conformal::MapKind::None) {
        rootFirst(session, [&] {
            const conformal::CubeMap map = engine::cubeMapFor(row.display, mapSize, "");
            raycaster.setCubeMap(map.size, map.rgba);
        });
    }
    const int total = static_cast<int>(result.job.poses.size());
    const std::vector<int> frameOf = deal(total, session.rank(), session.ranks());  // the row's frame of each of mine
    engine::CoverageJob mine = result.job;
    mine.poses = dealt(result.job.poses, session);
    const bool isReporting = isReporter(session);
    if (isReporting && report.say) report.say("coverage: " + row.name + ": " + std::to_string(total) + " frame(s)");
    engine::CoverageHooks hooks;
    // Rank 0 shows the whole row: the frames whose sheets are in the folder, whoever wrote them.
    const auto framesWritten = [&] {
        int done = 0;
        for (int i = 0; i < total; ++i) done += fs::exists(folder / engine::frameFolderName(i) / "sheet.png") ? 1 : 0;
        return done;
    };
    hooks.onProgress = [&](int, int) {
        if (isReporting && report.onProgress) report.onProgress(framesWritten(), total);
    };
    hooks.onFrame = [&](int index, const std::vector<engine::WallImage>& walls) {
        const auto start = std::chrono::steady_clock::now();
        engine::writeCoverageSheet(folder, frameOf[static_cast<std::size_t>(index)], result.job.display, walls);
        result.sheetSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    };
    try {
        result.run = engine::runCoverage(raycaster, mine, coverage, hooks);
    } catch (...) {
        if (isReporting && report.onFramesDone) report.onFramesDone();
        throw;
    }
    // What each frame showed first, by the row's frame index, for rank 0 to merge.
    nlohmann::json shown = nlohmann::json::array();
    for (std::size_t f = 0; f < result.run.frames.size(); ++f) shown.push_back({frameOf[f], result.run.frames[f].newlySeenElements});
    const std::vector<std::string> all = gatherAtRoot(session, shown.dump());
    if (isReporting) {
        if (report.onProgress) report.onProgress(total, total);
        if (report.onFramesDone) report.onFramesDone();
    }
    if (!isReporting) return result;
    std::vector<std::vector<uint32_t>> byFrame(result.job.poses.size());
    for (const std::string& text : all) {
        for (const auto& entry : nlohmann::json::parse(text)) {
            byFrame.at(entry[0].get<std::size_t>()) = entry[1].get<std::vector<uint32_t>>();
        }
    }
    coverage = engine::mergedCoverage(coverage.surface(), settings.coverage, byFrame, result.cumulativePercent);
    return result;
}

}  // namespace

nlohmann::json coverageRowOverRanks(MpiSession& session, const engine::CoverageStudySettings& settings,
                                    const engine::CoverageRow& row, const engine::CoverageScene& scene,
                                    engine::Raycaster& raycaster, int mapSize, const std::string& rendererDescription,
                                    const fs::path& folder, const CoverageReport& report) {
    engine::validateDisplay(row.display);
    if (isReporter(session)) fs::create_directories(folder);
    session.barrier();
    colon::SurfaceCoverage coverage(scene.wall, settings.coverage);
    engine::CoverageRowResult result =
        flyAndMeasure(session, settings, row, scene, raycaster, mapSize, coverage, folder, report);
    if (!isReporter(session)) return nullptr;  // rank 0 has every rank's frames: it reports the row
    engine::locateAndPictureUnseen(settings, scene, raycaster, coverage, result, folder);
    engine::writeTextFile(folder / "unseen_patches.mrk.json", colon::unseenPatchesMarkupsJson(result.patches, scene.loaded.volume));
    const nlohmann::json doc = engine::coverageRowJson(settings, row, coverage, result, rendererDescription, session.ranks());
    engine::writeTextFile(folder / "coverage.json", doc.dump(1) + "\n");
    engine::writeCoverageRowPage(settings, row, scene, coverage, result, rendererDescription, folder);
    if (report.tell) {
        std::ostringstream line;
        line << std::fixed << std::setprecision(1) << row.name << ": " << coverage.percent() << " % of "
             << coverage.wallAreaMm2() / 100.0 << " cm^2 seen over " << result.job.poses.size() << " frames, "
             << result.patches.size() << " unseen patch(es) of " << settings.minPatchMm2 << " mm^2 or more; "
             << std::setprecision(2) << result.run.seconds << " s (measuring " << result.run.measureSeconds << " s)";
        report.tell(line.str());
    }
    return doc;
}

}  // namespace distribution
