/// @brief The polyp check shared over the ranks of a run (one process: all of it, on the same
/// code path): the polyps dealt out, the maps baked by rank 0 first, every rank's results
/// gathered on rank 0 in the order one process gives them, and the document made there.
#pragma once

#include <filesystem>
#include <functional>

#include <nlohmann/json.hpp>

#include "distribution/mpi_session.h"
#include "engine/render/raycaster.h"
#include "engine/studies/polyp_check_report.h"
#include "engine/studies/polyp_check_request.h"

namespace distribution {

/// Checks this rank's share of `job`'s polyps with `raycaster` (the volume's), writes their
/// crops into `cropsFolder` (made if missing; empty: no crops) and returns, on rank 0, the
/// document polyp_check.json holds (null on the other ranks). `onProgress(done, total)` counts
/// this rank's rendered frames.
nlohmann::json checkPolypsOverRanks(MpiSession& session, engine::Raycaster& raycaster, const engine::PolypCheckJob& job,
                                    int mapSize, const engine::PolypCheckSources& sources,
                                    const std::filesystem::path& cropsFolder,
                                    const std::function<void(int, int)>& onProgress = {});

}  // namespace distribution
