/// @brief `cvc_bench polyline`: how far a stereo eye's bent ray (the exact warp's curve
/// W(e + t d)) strays from the straight pieces that march it: the paper's one chord from the near
/// plane to the far end, and the polyline warp's pieces (shaders/polyline_warp.glsl, rebuilt here
/// on the CPU from the same cube map). Over directions spread evenly on the display's walls, the
/// worst distance within three ranges of t, in footprints of a pixel there (the wall's pixel angle
/// times t times the map's local scale); percentiles over the directions, as JSON.
#pragma once

#include <string>
#include <vector>

namespace bench {

struct PolylineStudyRequest {
    std::string display = "ic5";
    std::vector<double> mmPerMetre{4.0, 10.0};
    int mapSize = 1024;
    int directions = 6000;
};

void runPolylineStudy(const PolylineStudyRequest& request);

}  // namespace bench
