/// @brief A polyp check as it is asked for (cvc polyp-check's options, cvc.polyp_check's
/// keywords) turned into the check's job, and the cube maps of its maps.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "conformal/cube_map.h"
#include "engine/studies/polyp_check.h"

namespace engine {

struct PolypCheckRequest {
    std::string truthPath;   ///< a ground truth with polyps and a centreline
    bool isCandidateList = false;  ///< truthPath is cvc candidates' candidates.json (colon::readCandidatesAsPolyps)
    std::string display = "ic5";  ///< a preset or a display JSON file with a missing wall
    int wallWidth = 0;       ///< the box's width in pixels, every wall at that density; 0: the display's own
    std::vector<int> polyps;         ///< by index in the truth; empty: every polyp
    std::vector<std::string> poses;  ///< by name; empty: every pose of the display
    std::vector<std::string> maps{"conformal", "linear", "none"};
    int mapSize = 1024;              ///< the baked maps' face size
    double mmPerMetre = 10.0;
    std::string warp = "eye-centred";
    double angularRadiusDeg = 5.0;   ///< the most a polyp may subtend from the eye
};

/// The check's job: the display with its walls, the truth's polyps and centreline, the poses and
/// maps by name, the warp, and the settings every polyp check renders with; the tolerance that
/// follows the volume's spacing is the caller's to set (colon::polypToleranceMm), once it has
/// loaded the volume. Throws std::invalid_argument naming the option for a
/// display without a map, a scale, map size or radius out of range, maps without the conformal
/// one, an unknown pose, map or warp; and the truth reader's errors for a bad truth file.
PolypCheckJob polypCheckJobOf(const PolypCheckRequest& request);

/// The cube maps of job.maps that bend rays, baked or found in the cache.
std::map<conformal::MapKind, conformal::CubeMap> polypCheckCubeMaps(const PolypCheckJob& job, int mapSize);

/// A lookup of those maps by kind, for planPolypCheck and checkPolyps.
CubeMapLookup cubeMapLookupOf(const std::map<conformal::MapKind, conformal::CubeMap>& cubeMaps);

}  // namespace engine
