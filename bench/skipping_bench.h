/// @brief `cvc_bench skipping`: what empty-space skipping costs or saves on one pinhole view.
/// The view is rendered at each step size three ways, alternated within one process (the
/// volume loaded and the pipelines built once, so that only the march differs): without
/// skipping, with skipping and the tile pass deciding per tile whether the march looks at the
/// distance map (the default), and with the march looking in every tile.
#pragma once

#include <vector>

#include "bench/pinhole_scene.h"

namespace bench {

struct SkippingBenchRequest {
    PinholeScene scene;
    std::vector<double> stepsVoxels = {0.25, 0.5, 1.0, 2.0};
    int runs = 5;
};

/// Prints, as one JSON object on stdout, the device time of every run, step and variant, their
/// medians, the paired ratios' medians (no skipping / each variant) and the largest channel
/// difference between the variants' images (0 but for float rounding: a fixed step takes the
/// same samples). Progress goes to stderr.
void runSkippingBench(const SkippingBenchRequest& request);

}  // namespace bench
