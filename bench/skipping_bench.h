/// @brief `cvc_bench skipping`: what empty-space skipping costs or saves on one pinhole view.
/// The view is rendered at each step size three ways, alternated within one process (the
/// volume loaded and the pipelines built once, so that only the march differs): without
/// skipping, with skipping and the tile pass deciding per tile whether the march looks at the
/// distance map (the default), and with the march looking in every tile.
#pragma once

#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace bench {

struct SkippingBenchRequest {
    std::string volumePath;
    glm::dvec3 positionMm{0.0};
    glm::dvec3 lookAtMm{0.0, 0.0, 1.0};
    glm::dvec3 up{0.0, 0.0, 1.0};
    double fovDeg = 90.0;
    int size = 1024;
    std::string mode = "iso";            // or "composite"
    double isoHu = -500.0;
    std::string transferFunction = "colon-wall";
    std::string gradient = "bspline";    // or "central" (shading normals)
    std::vector<double> stepsVoxels = {0.25, 0.5, 1.0, 2.0};
    int runs = 5;
    std::string device;
};

/// Prints, as one JSON object on stdout, the device time of every run, step and variant, their
/// medians, the paired ratios' medians (no skipping / each variant) and the largest channel
/// difference between the variants' images (0: a fixed step takes the same samples). Progress
/// goes to stderr.
void runSkippingBench(const SkippingBenchRequest& request);

}  // namespace bench
