#include "bench/skipping_bench.h"

#include <algorithm>
#include <array>
#include <cstdlib>
#include <iostream>
#include <map>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "bench/bench_statistics.h"
#include "bench/image_difference.h"

namespace bench {
namespace {

const std::array<std::string, 3> kVariants = {"none", "per_tile", "every_tile"};

engine::RenderSettings variantSettings(const PinholeScene& scene, double stepVoxels, const std::string& variant) {
    engine::RenderSettings settings = settingsFor(scene, stepVoxels);
    settings.isSkipping = variant != "none";
    settings.isLookingInEveryTile = variant == "every_tile";
    return settings;
}

}  // namespace

void runSkippingBench(const SkippingBenchRequest& request) {
    if (request.runs < 1 || request.runs > 1000) throw std::invalid_argument("--runs must be 1 to 1000");
    if (request.stepsVoxels.empty() || request.stepsVoxels.size() > 16) {
        throw std::invalid_argument("--steps: 1 to 16 steps");
    }
    LoadedScene loaded(request.scene);
    const engine::ViewRays rays = raysFor(request.scene);

    nlohmann::json out;
    out["device"] = loaded.context.driverDescription();
    out["volume"] = request.scene.volumePath;
    out["mode"] = request.scene.mode;
    for (const double step : request.stepsVoxels) {
        std::map<std::string, engine::RenderedImage> images;
        for (const auto& variant : kVariants) {
            images[variant] = loaded.raycaster.render(rays, variantSettings(request.scene, step, variant));
        }
        std::map<std::string, std::vector<double>> times;
        for (int run = 0; run < request.runs; ++run) {
            for (std::size_t k = 0; k < kVariants.size(); ++k) {  // each run starts with another variant
                const std::string& variant = kVariants[(k + static_cast<std::size_t>(run)) % kVariants.size()];
                const auto settings = variantSettings(request.scene, step, variant);
                times[variant].push_back(loaded.raycaster.render(rays, settings).deviceMs);
                std::cerr << "skipping: step " << step << ", run " << run + 1 << "/" << request.runs << ", "
                          << variant << ": " << times[variant].back() << " ms\n";
            }
        }
        nlohmann::json result;
        result["step_voxels"] = step;
        result["device_ms"] = times;
        for (const auto& variant : kVariants) {
            result["median_ms"][variant] = median(times[variant]);
            std::vector<double> ratios;
            for (int run = 0; run < request.runs; ++run) ratios.push_back(times["none"][run] / times[variant][run]);
            result["median_ratio_none_over"][variant] = median(ratios);
        }
        ImageDifference againstNone, againstEveryTile;
        againstNone.add(images["per_tile"], images["none"]);
        againstEveryTile.add(images["per_tile"], images["every_tile"]);
        result["largest_channel_difference"] = {{"per_tile_vs_none", againstNone.largestChannel},
                                                {"per_tile_vs_every_tile", againstEveryTile.largestChannel}};
        out["steps"].push_back(result);
    }
    std::cout << out.dump(2) << '\n';
}

}  // namespace bench
