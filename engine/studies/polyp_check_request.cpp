#include "engine/studies/polyp_check_request.h"

#include <algorithm>
#include <stdexcept>

#include "colon/polyp_truth.h"
#include "engine/display/display_json.h"
#include "engine/display/display_map.h"

namespace engine {

PolypCheckJob polypCheckJobOf(const PolypCheckRequest& request) {
    Display display = loadDisplay(request.display);
    if (request.wallWidth > 0) resizeWallsToWidth(display, request.wallWidth);
    validateDisplay(display);
    if (display.map == conformal::MapKind::None) {
        throw std::invalid_argument("display '" + display.name + "' has no map to check (it misses no wall)");
    }
    if (!(request.mmPerMetre > 0.0 && request.mmPerMetre <= 1000.0)) {
        throw std::invalid_argument("--scale must be in (0, 1000] mm per metre");
    }
    if (request.mapSize < 16 || request.mapSize > 4096) throw std::invalid_argument("--map-size must be 16..4096");
    if (!(request.angularRadiusDeg >= 1.0 && request.angularRadiusDeg <= 30.0)) {
        throw std::invalid_argument("--angular-radius must be 1..30 degrees");
    }

    PolypCheckJob job;
    job.display = display;
    job.polyps = request.isCandidateList ? colon::readCandidatesAsPolyps(request.truthPath)
                                         : colon::readPolypTruth(request.truthPath);
    job.centreline = readCentreline(request.truthPath);
    if (job.centreline.anterior) job.path.initialUp = *job.centreline.anterior;
    if (request.polyps.empty()) {
        for (int i = 0; i < static_cast<int>(job.polyps.size()); ++i) job.polypIndices.push_back(i);
    } else {
        job.polypIndices = request.polyps;
    }
    job.mmPerMetre = request.mmPerMetre;
    job.poses = polypPosesNamed(display, request.poses);
    job.maps.clear();
    for (const std::string& name : request.maps) {
        const conformal::MapKind kind = conformal::mapKindFromName(name);
        if (std::find(job.maps.begin(), job.maps.end(), kind) == job.maps.end()) job.maps.push_back(kind);
    }
    if (std::find(job.maps.begin(), job.maps.end(), conformal::MapKind::Conformal) == job.maps.end()) {
        throw std::invalid_argument("--maps must include conformal: its prediction places the eyes and sets the targets");
    }
    job.angularRadiusDeg = request.angularRadiusDeg;
    job.minAngularRadiusDeg = std::min(job.minAngularRadiusDeg, request.angularRadiusDeg);
    job.warpMode = warpModeFromName(request.warp);
    job.settings.gradient = GradientFilter::Central;
    job.settings.lightHalfDistanceMm = 25.0;
    return job;
}

std::map<conformal::MapKind, conformal::CubeMap> polypCheckCubeMaps(const PolypCheckJob& job, int mapSize) {
    std::map<conformal::MapKind, conformal::CubeMap> cubeMaps;
    for (conformal::MapKind kind : job.maps) {
        if (kind == conformal::MapKind::None) continue;
        Display withMap = job.display;
        withMap.map = kind;
        cubeMaps[kind] = cubeMapFor(withMap, mapSize, "");
    }
    return cubeMaps;
}

CubeMapLookup cubeMapLookupOf(const std::map<conformal::MapKind, conformal::CubeMap>& cubeMaps) {
    return [&cubeMaps](conformal::MapKind kind) -> const conformal::CubeMap& { return cubeMaps.at(kind); };
}

}  // namespace engine
