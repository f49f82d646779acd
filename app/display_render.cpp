/// @brief `cvc render --display`: every wall of an immersive display for both eyes, at one
/// pose or along a path, bent through the display's map.
#include <cmath>
#include <iostream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "app/frame_sequence.h"
#include "app/option_parsing.h"
#include "app/render_options.h"
#include "conformal/cube_map_baker.h"
#include "engine/camera_path.h"
#include "engine/display_json.h"
#include "engine/gpu_context.h"
#include "engine/volume_texture.h"
#include "volumes/load_volume.h"

namespace app {
namespace {

/// The poses asked for: beneath a polyp, along a path, or the one given by --position.
std::vector<engine::CameraPose> posesFrom(const RenderOptions& options) {
    engine::PathSettings path;
    path.stepMm = options.pathStepMm;
    path.smoothingMm = options.smoothingMm;
    path.direction = options.isRetrograde ? engine::Direction::Retrograde : engine::Direction::Antegrade;
    if (!options.pathFile.empty()) {
        const auto polyline = engine::readPolyline(options.pathFile);
        if (options.polyp >= 0) {
            const auto centres = engine::readPolypCentres(options.pathFile);
            if (options.polyp >= static_cast<int>(centres.size())) {
                throw std::invalid_argument("--polyp " + std::to_string(options.polyp) + ": " + options.pathFile +
                                            " lists " + std::to_string(centres.size()) + " polyps");
            }
            return {engine::poseViewing(polyline, centres[static_cast<std::size_t>(options.polyp)],
                                        options.polypElevationDeg, path)};
        }
        auto poses = engine::posesAlong(polyline, path);
        if (options.maxFrames > 0 && static_cast<int>(poses.size()) > options.maxFrames) {
            poses.resize(static_cast<std::size_t>(options.maxFrames));
        }
        return poses;
    }
    if (options.positionMm.empty() || options.lookAtMm.empty()) {
        throw std::invalid_argument("a display render needs --path, or --position and --look-at");
    }
    engine::CameraPose pose;
    pose.positionMm = vec3From(options.positionMm, "--position");
    const glm::dvec3 view = vec3From(options.lookAtMm, "--look-at") - pose.positionMm;
    if (glm::length(view) < 1e-9) throw std::invalid_argument("--look-at equals --position");
    pose.forward = glm::normalize(view);
    const glm::dvec3 up = options.up.empty() ? glm::dvec3(0.0, 0.0, 1.0) : vec3From(options.up, "--up");
    const glm::dvec3 orthogonal = up - glm::dot(up, pose.forward) * pose.forward;
    if (glm::length(orthogonal) < 1e-9) throw std::invalid_argument("--up is parallel to the view direction");
    pose.up = glm::normalize(orthogonal);
    return {pose};
}

/// Everything that determines the images, so --resume can refuse a changed request.
std::string manifestOf(const RenderOptions& options, const engine::Display& display,
                       const std::vector<engine::CameraPose>& poses, const engine::RenderSettings& s) {
    nlohmann::json manifest;
    manifest["volume"] = std::filesystem::absolute(options.volumePath).string();
    manifest["display"] = nlohmann::json::parse(engine::displayJson(display));
    manifest["map_size"] = options.mapSize;
    manifest["warp"] = options.warp;
    manifest["mm_per_metre"] = options.mmPerMetre;
    manifest["before_after"] = options.isWritingBeforeAfter;
    manifest["settings"] = {{"mode", options.mode},          {"iso_hu", s.isoHu},
                            {"transfer_function", s.transferFunction}, {"step_voxels", s.stepVoxels},
                            {"refinement_steps", s.refinementSteps}, {"filter", options.filter},
                            {"skipping", s.isSkipping},       {"skip_cell_voxels", s.skipCellVoxels},
                            {"adaptive", s.isAdaptive},       {"early_termination", s.earlyTerminationOpacity},
                            {"jitter", s.isJittered},          {"jitter_seed", s.jitterSeed},
                            {"light_half_distance_mm", s.lightHalfDistanceMm}};
    nlohmann::json posesJson = nlohmann::json::array();
    for (const auto& pose : poses) {
        posesJson.push_back({{"position_mm", {pose.positionMm.x, pose.positionMm.y, pose.positionMm.z}},
                             {"forward", {pose.forward.x, pose.forward.y, pose.forward.z}},
                             {"up", {pose.up.x, pose.up.y, pose.up.z}}});
    }
    manifest["poses"] = posesJson;
    return manifest.dump(2) + "\n";
}

}  // namespace

void runDisplayRender(const RenderOptions& options) {
    engine::Display display = engine::loadDisplay(options.display);
    if (!options.map.empty()) display.map = engine::mapChoiceFromText(options.map);
    engine::validateDisplay(display);
    if (!(options.mmPerMetre > 0.0 && options.mmPerMetre <= 1000.0)) {
        throw std::invalid_argument("--scale must be in (0, 1000] mm per metre");
    }
    if (options.mapSize < 16 || options.mapSize > 4096) throw std::invalid_argument("--map-size must be 16..4096");
    const std::vector<engine::CameraPose> poses = posesFrom(options);
    const engine::RenderSettings settings = renderSettingsFrom(options, true);

    SequenceJob job;
    job.display = display;
    job.poses = poses;
    job.mmPerMetre = options.mmPerMetre;
    job.settings = settings;
    job.warpMode = options.warp == "exact" ? engine::WarpMode::Exact : engine::WarpMode::Chord;
    job.isWritingBeforeAfter = options.isWritingBeforeAfter;
    job.manifestJson = manifestOf(options, display, poses, settings);

    volumes::LoadOptions load;
    if (!options.rawSpec.empty()) load.raw = volumes::parseRawSpec(options.rawSpec);
    const volumes::LoadedVolume loaded = volumes::loadVolumeWithBricks(options.volumePath, load);
    engine::GpuContext context(engine::GpuContextOptions{false, options.device});
    engine::VolumeTexture texture(context, loaded.volume);
    engine::Raycaster raycaster(context, loaded.volume, texture, loaded.bricks);
    if (display.map != engine::MapChoice::None) {
        conformal::BakeSettings bake;
        bake.size = options.mapSize;
        bake.box.size = display.boxSizeM;
        bake.kind = display.map == engine::MapChoice::Linear ? conformal::MapKind::Linear : conformal::MapKind::Conformal;
        conformal::BakeReport report;
        const conformal::CubeMap map = conformal::cachedCubeMap(bake, &report);
        std::cerr << "map: " << conformal::mapKindName(bake.kind) << ", " << map.size << "^2 per face, "
                  << (report.wasLoadedFromCache ? "loaded from " + report.cachePath.string()
                                                : "computed in " + std::to_string(report.mapSeconds + report.bakeSeconds) + " s")
                  << '\n';
        raycaster.setCubeMap(map.size, map.rgba);
    }

    const SequenceSummary summary =
        renderSequence(raycaster, job, SequenceOutput{options.outPath, options.force, options.resume});
    const int images = summary.framesRendered * 2 * static_cast<int>(display.walls.size());
    std::cout << "rendered " << summary.framesRendered << " frame(s) (" << images << " wall images) on "
              << context.deviceName() << " in " << summary.seconds << " s";
    if (summary.framesRendered > 0) {
        std::cout << ", " << summary.seconds / summary.framesRendered << " s per frame (ray casting "
                  << summary.rayCastingMs / summary.framesRendered << " ms of device time per stereo frame)";
    }
    if (summary.framesKept > 0) std::cout << "; kept " << summary.framesKept << " finished frame(s)";
    std::cout << "\nwrote " << options.outPath << '\n';
}

}  // namespace app
