#include "distribution/polyp_check_over_ranks.h"

#include <map>
#include <string>
#include <vector>

#include "distribution/work_share.h"

namespace distribution {

nlohmann::json checkPolypsOverRanks(MpiSession& session, engine::Raycaster& raycaster, const engine::PolypCheckJob& job,
                                    int mapSize, const engine::PolypCheckSources& sources,
                                    const std::filesystem::path& cropsFolder,
                                    const std::function<void(int, int)>& onProgress) {
    // Rank 0 bakes or finds the maps first; the others then load them from the cache it filled.
    std::map<conformal::MapKind, conformal::CubeMap> cubeMaps;
    rootFirst(session, [&] { cubeMaps = engine::polypCheckCubeMaps(job, mapSize); });
    const engine::CubeMapLookup lookup = engine::cubeMapLookupOf(cubeMaps);
    const engine::PolypCheckPlan plan = engine::planPolypCheck(job, lookup);

    // This rank's polyps: the r-th, the (r + N)-th, ... of those asked for.
    engine::PolypCheckJob mine = job;
    mine.polypIndices = dealt(job.polypIndices, session);
    const std::vector<engine::PolypViewResult> results = engine::checkPolyps(raycaster, mine, plan, lookup, onProgress);
    // One file per polyp, pose and eye: each rank its own, once the check succeeded.
    if (!cropsFolder.empty()) {
        std::filesystem::create_directories(cropsFolder);
        engine::writePolypCrops(results, cropsFolder, job.cropSize);
    }
    // Rank 0 puts every rank's entries in the order one process gives them.
    const std::vector<std::string> all = gatherAtRoot(session, engine::polypResultEntries(results, plan).dump());
    if (!isReporter(session)) return nullptr;
    return engine::polypCheckDocument(nlohmann::json(engine::polypEntriesInOrder(all, job, plan)), sources, job, plan);
}

}  // namespace distribution
