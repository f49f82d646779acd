/// @brief `cvc_bench view`: one pinhole view timed the way ../shared/bench/vtk/render.py times
/// VTK's ray caster, so that the two compare like for like: the first render, then `repeats`
/// further renders with the eye turned 0.3 degrees further about the focal point each time (so
/// that nothing from an earlier frame can serve), and their median. The ray-casting device
/// time of each render (`cvc render` prints that of its one, first, frame).
#pragma once

#include <string>

#include "bench/pinhole_scene.h"

namespace bench {

struct ViewBenchRequest {
    PinholeScene scene;
    double stepVoxels = 0.5;
    bool isSkipping = true;
    int skipCellVoxels = 2;
    std::string filter = "trilinear";  // or "tricubic"
    int refinementSteps = 2;           // iso mode's bisection steps, as `cvc render --refine`
    bool isAdaptive = false;           // as `cvc render --adaptive`
    int repeats = 5;
    double azimuthStepDeg = 0.3;
};

/// Prints one JSON line on stdout: first_ms, median_ms, min_ms and every repeat's time.
void runViewBench(const ViewBenchRequest& request);

}  // namespace bench
