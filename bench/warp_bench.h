/// @brief `cvc_bench warp`: the warp's own cost. One stereo display frame rendered four ways,
/// alternating: through the display's map (the baked cube map, chord warp), through an identity
/// cube map of the same size and format (the same texture fetches and arithmetic, but straight
/// rays: the same geometry as no warp) reading the chord table and fetching per ray, and
/// without the warp. identity / none is what the warp costs; conformal / none adds what the
/// bent rays see differently.
#pragma once

#include <string>

#include "bench/display_frame_scene.h"

namespace bench {

struct WarpBenchRequest {
    DisplayFrameRequest frame;
    double mmPerMetre = 10.0;
};

/// Prints the device time of each run and mode, their medians, the paired ratios' medians, and
/// how far the identity-warped images are from the unwarped ones, as one JSON object on stdout.
void runWarpBench(const WarpBenchRequest& request);

}  // namespace bench
