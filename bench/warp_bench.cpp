#include "bench/warp_bench.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <map>
#include <stdexcept>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/bench_statistics.h"
#include "bench/display_frame_scene.h"
#include "bench/image_difference.h"
#include "conformal/cube_map_baker.h"
#include "conformal/direction_map.h"
#include "engine/core/gpu_context.h"
#include "engine/display/display_map.h"
#include "engine/render/raycaster.h"
#include "engine/render/volume_texture.h"
#include "engine/sequence/frame_sequence.h"
#include "volumes/brick_minmax.h"

namespace bench {
namespace {

/// F = identity: every display direction shows the scene direction it points at.
class IdentityMap final : public conformal::DirectionMap {
public:
    glm::dvec3 sceneFromDisplay(const glm::dvec3& display) const override { return glm::normalize(display); }
    glm::dvec3 displayFromScene(const glm::dvec3& scene) const override { return glm::normalize(scene); }
};

}  // namespace

void runWarpBench(const WarpBenchRequest& request) {
    const DisplayFrameScene scene = loadDisplayFrameScene(request.frame);
    const volumes::Volume& volume = scene.volume;
    const volumes::BrickMinMax& bricks = scene.bricks;
    const engine::Display& display = scene.display;
    const engine::CameraPose& pose = scene.pose;
    const engine::ScenePose scenePose{pose.positionMm, pose.forward, pose.up, request.mmPerMetre};

    engine::GpuContext context(engine::GpuContextOptions{false, request.frame.device});
    engine::VolumeTexture texture(context, volume);
    // One ray caster per map: binding another cube map drops the chord tables made with the old.
    engine::Raycaster conformalCaster(context, volume, texture, bricks);
    engine::Raycaster identityCaster(context, volume, texture, bricks);
    const conformal::CubeMap map = engine::cubeMapFor(display, request.frame.mapSize, "");
    const conformal::CubeMap identity =
        conformal::bakeCubeMap(IdentityMap{}, engine::bakeSettingsFor(display, map.size).box, map.kind, map.size);

    const engine::RenderSettings settings = displayFrameSettings();
    const engine::Eye eyes[] = {engine::Eye::Left, engine::Eye::Right};
    conformalCaster.setCubeMap(map.size, map.rgba);
    identityCaster.setCubeMap(identity.size, identity.rgba);
    // "identity" reads the chord table (the default); "identity_per_ray" fetches the two texels
    // per ray, as every frame did before the table.
    const std::array<std::string, 4> modes = {"conformal", "identity", "identity_per_ray", "none"};
    const auto renderMode = [&](const std::string& mode, bool isCountingFetches = false) {
        engine::RenderSettings modeSettings = settings;
        modeSettings.isWritingHits = isCountingFetches;
        modeSettings.isCountingFetches = isCountingFetches;
        modeSettings.isUsingChordTable = mode != "identity_per_ray";
        engine::Raycaster& raycaster = mode == "conformal" ? conformalCaster : identityCaster;
        return engine::renderWalls(raycaster, display, scenePose, eyes, modeSettings,
                                   mode == "none" ? engine::WarpMode::None : engine::WarpMode::Chord);
    };
    const auto deviceMs = [](const std::vector<engine::WallImage>& walls) {
        double ms = 0.0;
        for (const auto& wall : walls) ms += std::max(wall.image.deviceMs, 0.0);
        return ms;
    };

    // Volume fetches per ray, from one counted render per mode (counting is a pipeline of its
    // own, so the timed renders below do not count).
    std::map<std::string, double> fetchesPerRay;
    for (const auto& mode : modes) {
        double fetches = 0.0, rays = 0.0;
        for (const auto& wall : renderMode(mode, true)) {
            const engine::FetchCounts counts = engine::fetchCountsOf(wall.image);
            fetches += counts.total;
            rays += counts.rays;
        }
        fetchesPerRay[mode] = rays > 0.0 ? fetches / rays : 0.0;
    }
    std::map<std::string, std::vector<double>> times;
    for (const auto& mode : modes) renderMode(mode);  // warm: pipelines built, caches filled
    ImageDifference identityAgainstNone;
    const std::vector<engine::WallImage> identityWalls = renderMode("identity"), plainWalls = renderMode("none");
    if (identityWalls.size() != plainWalls.size()) throw std::runtime_error("warp bench: different walls");
    for (std::size_t w = 0; w < identityWalls.size(); ++w) {
        identityAgainstNone.add(identityWalls[w].image, plainWalls[w].image);
    }
    for (int run = 0; run < request.frame.runs; ++run) {
        for (std::size_t k = 0; k < modes.size(); ++k) {  // each run starts with another mode
            const std::string& mode = modes[(k + static_cast<std::size_t>(run)) % modes.size()];
            times[mode].push_back(deviceMs(renderMode(mode)));
            std::cerr << "warp: run " << run + 1 << "/" << request.frame.runs << ", " << mode << ": " << times[mode].back()
                      << " ms\n";
        }
    }
    std::vector<double> identityRatio, perRayRatio, conformalRatio;
    for (int run = 0; run < request.frame.runs; ++run) {
        identityRatio.push_back(times["identity"][run] / times["none"][run]);
        perRayRatio.push_back(times["identity_per_ray"][run] / times["none"][run]);
        conformalRatio.push_back(times["conformal"][run] / times["none"][run]);
    }
    nlohmann::json out;
    out["display"] = request.frame.display;
    out["map_size"] = map.size;
    out["device"] = context.driverDescription();
    out["device_ms"] = times;
    for (const auto& mode : modes) out["median_ms"][mode] = median(times[mode]);
    out["fetches_per_ray"] = fetchesPerRay;
    out["median_ratio"] = {{"identity_over_none", median(identityRatio)},
                           {"identity_per_ray_over_none", median(perRayRatio)},
                           {"conformal_over_none", median(conformalRatio)}};
    out["ratios"] = {{"identity_over_none", identityRatio},
                     {"identity_per_ray_over_none", perRayRatio},
                     {"conformal_over_none", conformalRatio}};
    out["identity_against_none"] = {{"largest_channel_difference", identityAgainstNone.largestChannel},
                                    {"pixels_over_2_levels", identityAgainstNone.shareOver2Levels()}};
    std::cout << out.dump(2) << '\n';
}

}  // namespace bench
