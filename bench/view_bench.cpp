#include "bench/view_bench.h"

#include <algorithm>
#include <iostream>
#include <stdexcept>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/bench_statistics.h"

namespace bench {

void runViewBench(const ViewBenchRequest& request) {
    if (request.repeats < 1 || request.repeats > 1000) throw std::invalid_argument("--repeats must be 1 to 1000");
    LoadedScene loaded(request.scene);
    engine::RenderSettings settings = settingsFor(request.scene, request.stepVoxels);
    settings.isSkipping = request.isSkipping;
    settings.skipCellVoxels = request.skipCellVoxels;
    settings.filter = request.filter == "tricubic" ? engine::VolumeFilter::Tricubic : engine::VolumeFilter::Trilinear;
    settings.refinementSteps = request.refinementSteps;
    settings.isAdaptive = request.isAdaptive;
    const double firstMs = loaded.raycaster.render(raysFor(request.scene), settings).deviceMs;
    std::vector<double> times;
    for (int repeat = 1; repeat <= request.repeats; ++repeat) {
        const engine::ViewRays rays = raysFor(request.scene, repeat * request.azimuthStepDeg);
        times.push_back(loaded.raycaster.render(rays, settings).deviceMs);
        std::cerr << "view: repeat " << repeat << "/" << request.repeats << ": " << times.back() << " ms\n";
    }
    nlohmann::json out;
    out["device"] = loaded.context.driverDescription();
    out["first_ms"] = firstMs;
    out["median_ms"] = median(times);
    out["min_ms"] = *std::min_element(times.begin(), times.end());
    out["times_ms"] = times;
    std::cout << out.dump() << '\n';
}

}  // namespace bench
