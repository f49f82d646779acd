#include "bench/stereo_bench.h"

#include <array>
#include <iostream>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/bench_statistics.h"
#include "bench/display_frame_scene.h"
#include "bench/image_difference.h"
#include "conformal/cube_map_speed.h"
#include "engine/core/gpu_context.h"
#include "engine/display/display_map.h"
#include "engine/render/raycaster.h"
#include "engine/render/volume_texture.h"
#include "engine/sequence/frame_sequence.h"
#include "volumes/brick_minmax.h"

namespace bench {
namespace {

/// A way to march the bent rays: the warp, and for the exact warp whether it skips along them.
struct StereoMode {
    std::string name;
    engine::WarpMode warp;
    bool isSkippingBentRays = false;
};

const std::array<StereoMode, 5> kModes{{{"chord", engine::WarpMode::Chord},
                                         {"eye_centred", engine::WarpMode::EyeCentred},
                                         {"polyline", engine::WarpMode::Polyline},
                                         {"exact", engine::WarpMode::Exact},
                                         {"exact_skipping", engine::WarpMode::Exact, true}}};

double deviceMsOf(const std::vector<engine::WallImage>& walls) {
    double ms = 0.0;
    for (const auto& wall : walls) ms += std::max(wall.image.deviceMs, 0.0);
    return ms;
}

}  // namespace

void runStereoBench(const StereoBenchRequest& request) {
    if (request.mmPerMetre.empty()) throw std::invalid_argument("--scale needs at least one value");
    for (double scale : request.mmPerMetre) {
        if (!(scale > 0.0 && scale <= 1000.0)) throw std::invalid_argument("--scale values must be in (0, 1000]");
    }
    const DisplayFrameScene scene = loadDisplayFrameScene(request.frame);
    const volumes::Volume& volume = scene.volume;
    const volumes::BrickMinMax& bricks = scene.bricks;
    const engine::Display& display = scene.display;
    const engine::CameraPose& pose = scene.pose;

    engine::GpuContext context(engine::GpuContextOptions{false, request.frame.device});
    engine::VolumeTexture texture(context, volume);
    const conformal::CubeMap map = engine::cubeMapFor(display, request.frame.mapSize, "");
    const conformal::SpeedBoundMap bounds = conformal::speedBoundMap(map.size, map.rgba);
    const engine::RenderSettings settings = displayFrameSettings();
    const engine::Eye eyes[] = {engine::Eye::Left, engine::Eye::Right};

    nlohmann::json out;
    out["display"] = request.frame.display;
    out["map_size"] = map.size;
    out["device"] = context.driverDescription();
    out["polyp"] = request.frame.polyp;
    out["polyp_elevation_deg"] = request.frame.polypElevationDeg;
    for (double scale : request.mmPerMetre) {
        const engine::ScenePose scenePose{pose.positionMm, pose.forward, pose.up, scale};
        // A ray caster per mode: each keeps its own tables, as a render with that mode alone would
        // (together they would pass the tables' memory budget, and some would be filled anew for
        // every frame).
        std::map<std::string, std::unique_ptr<engine::Raycaster>> raycasters;
        for (const StereoMode& mode : kModes) {
            auto raycaster = std::make_unique<engine::Raycaster>(context, volume, texture, bricks);
            raycaster->setCubeMap(map.size, map.rgba);
            raycaster->setSpeedBounds(bounds.size, bounds.rgba);
            raycasters[mode.name] = std::move(raycaster);
        }
        const auto render = [&](const StereoMode& mode, bool isCountingFetches = false) {
            engine::RenderSettings modeSettings = settings;
            modeSettings.isSkippingBentRays = mode.isSkippingBentRays;
            modeSettings.isWritingHits = isCountingFetches;
            modeSettings.isCountingFetches = isCountingFetches;
            return engine::renderWalls(*raycasters.at(mode.name), display, scenePose, eyes, modeSettings, mode.warp);
        };
        nlohmann::json& entry = out["scales"][std::to_string(scale)];
        // The first frame of each mode fills its table (chord, polyline) and builds its pipelines.
        std::map<std::string, std::vector<engine::WallImage>> images;
        for (const StereoMode& mode : kModes) {
            images[mode.name] = render(mode);
            entry["first_frame_ms"][mode.name] = deviceMsOf(images[mode.name]);
        }
        for (const StereoMode& mode : kModes) {
            double fetches = 0.0, rays = 0.0;
            for (const auto& wall : render(mode, true)) {
                const engine::FetchCounts counts = engine::fetchCountsOf(wall.image);
                fetches += counts.total;
                rays += counts.rays;
            }
            entry["fetches_per_ray"][mode.name] = rays > 0.0 ? fetches / rays : 0.0;
        }
        const std::vector<engine::WallImage>& exact = images["exact"];
        for (const StereoMode& mode : kModes) {
            for (engine::Eye eye : eyes) {
                ImageDifference difference;
                for (std::size_t w = 0; w < exact.size(); ++w) {
                    if (exact[w].eye == eye) difference.add(images[mode.name][w].image, exact[w].image);
                }
                entry["against_exact"][mode.name][engine::eyeText(eye)] = {
                    {"p99_levels", difference.levelAtFraction(0.99)},
                    {"largest_levels", difference.largestChannel},
                    {"share_over_2_levels", difference.shareOver(2)},
                    {"share_over_16_levels", difference.shareOver(16)}};
            }
        }
        std::map<std::string, std::vector<double>> times;
        for (int run = 0; run < request.frame.runs; ++run) {
            for (std::size_t k = 0; k < kModes.size(); ++k) {  // each run starts with another mode
                const StereoMode& mode = kModes[(k + static_cast<std::size_t>(run)) % kModes.size()];
                times[mode.name].push_back(deviceMsOf(render(mode)));
                std::cerr << "stereo: scale " << scale << ", run " << run + 1 << "/" << request.frame.runs << ", "
                          << mode.name << ": " << times[mode.name].back() << " ms\n";
            }
        }
        entry["device_ms"] = times;
        for (const StereoMode& mode : kModes) {
            std::vector<double> ratios;
            for (int run = 0; run < request.frame.runs; ++run) ratios.push_back(times[mode.name][run] / times["chord"][run]);
            entry["median_ms"][mode.name] = median(times[mode.name]);
            entry["median_ratio_to_chord"][mode.name] = median(ratios);
        }
    }
    std::cout << out.dump(2) << '\n';
}

}  // namespace bench
