/// @brief A pinhole view of a volume as the benchmarks give it on the command line (the
/// camera, the image size and the features of `cvc render` they vary), and the ray caster that
/// renders it, set up once per process.
#pragma once

#include <memory>
#include <string>

#include <CLI/CLI.hpp>
#include <glm/glm.hpp>

#include "engine/core/gpu_context.h"
#include "engine/render/raycaster.h"
#include "engine/render/view_rays.h"
#include "engine/render/volume_texture.h"
#include "volumes/brick_minmax.h"
#include "volumes/volume.h"

namespace bench {

struct PinholeScene {
    std::string volumePath;
    glm::dvec3 positionMm{0.0};
    glm::dvec3 lookAtMm{0.0, 0.0, 1.0};  // the focal point: an azimuth turns the eye about it
    glm::dvec3 up{0.0, 0.0, 1.0};
    double fovDeg = 90.0;
    int size = 1024;
    std::string mode = "iso";            // or "composite"
    double isoHu = -500.0;
    std::string transferFunction = "colon-wall";
    std::string gradient = "bspline-voxels";  // or "bspline", "central" (shading normals), as a still
    bool isUsingGradientVolume = true;  // as `cvc render` for a still
    std::string device;
};

/// The scene's options (VOLUME, --position, --look-at, --up, --fov, --size, --mode, --iso, --tf,
/// --gradient, --gradient-volume, --device) on `command`.
void addPinholeSceneOptions(CLI::App* command, PinholeScene& scene);

/// The ray caster's settings for the scene at `stepVoxels`, hits not written; skipping as the
/// defaults have it.
engine::RenderSettings settingsFor(const PinholeScene& scene, double stepVoxels);

/// The scene's rays with the eye turned by `azimuthDeg` about the focal point, around the view's
/// up direction (VTK's vtkCamera::Azimuth).
engine::ViewRays raysFor(const PinholeScene& scene, double azimuthDeg = 0.0);

/// The volume on the device and its ray caster, loaded once.
struct LoadedScene {
    explicit LoadedScene(const PinholeScene& scene);

    volumes::Volume volume;
    volumes::BrickMinMax bricks;
    engine::GpuContext context;
    engine::VolumeTexture texture;
    engine::Raycaster raycaster;
};

}  // namespace bench
