/// @brief `cvc_bench stereo`: how the stereo eyes' bent rays are marched, time against error. One
/// stereo display frame at a polyp's pose rendered with each warp (chord, eye-centred, polyline,
/// exact, and exact skipping along its bent rays), alternating, at one or more scales; each mode's device
/// time, paired ratio to the chord's, volume fetches per ray, first frame (with its table's
/// fill) and, per eye, its difference to the exact warp's images (scripts/bench/bench_stereo.sh).
#pragma once

#include <vector>

#include "bench/display_frame_scene.h"

namespace bench {

struct StereoBenchRequest {
    StereoBenchRequest() { frame.polyp = 3; }  // the demo's polyp, on the cabin's missing ceiling
    DisplayFrameRequest frame;
    std::vector<double> mmPerMetre{4.0, 10.0};
};

/// Prints one JSON object on stdout: per scale, per mode the device times and their medians,
/// the medians of the per-run ratios to the chord, fetches per ray, the first frame's time, and
/// per eye the 99th-percentile level difference to the exact warp and the shares of pixels more
/// than 2 and 16 levels apart. Progress goes to stderr.
void runStereoBench(const StereoBenchRequest& request);

}  // namespace bench
