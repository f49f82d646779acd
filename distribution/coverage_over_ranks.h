/// @brief One row of the coverage study shared over the ranks of a run (one process: all of it,
/// on the same code path): the row's frames dealt out, each rank's first sightings gathered and
/// replayed in frame order on rank 0, which locates and pictures the unseen patches and writes
/// the row's folder.
#pragma once

#include <filesystem>
#include <functional>
#include <string>

#include <nlohmann/json.hpp>

#include "distribution/mpi_session.h"
#include "engine/render/raycaster.h"
#include "engine/studies/coverage_study.h"

namespace distribution {

/// What rank 0 reports as a row runs; any hook may be empty.
struct CoverageReport {
    std::function<void(const std::string& line)> say;     ///< a step (a progress line)
    std::function<void(int done, int total)> onProgress;  ///< the row's frames whose sheets are written
    std::function<void()> onFramesDone;                   ///< every frame of the row is flown
    std::function<void(const std::string& line)> tell;    ///< the row's result, one line
};

/// Flies this rank's share of the row's frames with `raycaster` (the scene's volume), marks what
/// they show and writes their sheets into `folder`; rank 0 then merges every rank's sightings,
/// locates and pictures the unseen patches, and writes coverage.json, coverage.png,
/// unseen_patches.mrk.json (for 3D Slicer), patches/ and the row's review page. Returns the
/// row's summary (coverage.json's content) on rank 0, null elsewhere.
nlohmann::json coverageRowOverRanks(MpiSession& session, const engine::CoverageStudySettings& settings,
                                    const engine::CoverageRow& row, const engine::CoverageScene& scene,
                                    engine::Raycaster& raycaster, int mapSize, const std::string& rendererDescription,
                                    const std::filesystem::path& folder, const CoverageReport& report = {});

}  // namespace distribution
