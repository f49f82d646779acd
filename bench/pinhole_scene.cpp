#include "bench/pinhole_scene.h"

#include <cmath>
#include <vector>

#include "volumes/load_volume.h"

namespace bench {
namespace {

/// An "x,y,z" option into `target`.
void addPointOption(CLI::App* command, const std::string& name, glm::dvec3& target, const std::string& description) {
    command->add_option_function<std::vector<double>>(
        name, [&target](const std::vector<double>& xyz) { target = {xyz[0], xyz[1], xyz[2]}; }, description)
        ->expected(3)->delimiter(',')->required();
}

/// `v` turned by `radians` about the unit `axis` (Rodrigues' formula).
glm::dvec3 rotated(const glm::dvec3& v, const glm::dvec3& axis, double radians) {
    const double c = std::cos(radians), s = std::sin(radians);
    return v * c + glm::cross(axis, v) * s + axis * glm::dot(axis, v) * (1.0 - c);
}

}  // namespace

void addPinholeSceneOptions(CLI::App* command, PinholeScene& scene) {
    command->add_option("volume", scene.volumePath, "Volume file")->required();
    addPointOption(command, "--position", scene.positionMm, "Eye position, mm");
    addPointOption(command, "--look-at", scene.lookAtMm, "Focal point, mm");
    addPointOption(command, "--up", scene.up, "Up direction");
    command->add_option("--fov", scene.fovDeg, "Vertical field of view, degrees")
        ->check(CLI::Range(1.0, 170.0))->capture_default_str();
    command->add_option("--size", scene.size, "Pixels per image side")
        ->check(CLI::Range(8, 4096))->capture_default_str();
    command->add_option("--mode", scene.mode, "iso or composite")
        ->check(CLI::IsMember({"iso", "composite"}))->capture_default_str();
    command->add_option("--iso", scene.isoHu, "Iso value, HU")->capture_default_str();
    command->add_option("--tf", scene.transferFunction, "Composite mode's transfer function")->capture_default_str();
    command->add_option("--gradient", scene.gradient, "Shading normals: bspline, bspline-voxels or central")
        ->check(CLI::IsMember({"bspline", "bspline-voxels", "central"}))->capture_default_str();
    command->add_option_function<std::string>(
        "--gradient-volume", [&scene](const std::string& value) { scene.isUsingGradientVolume = value == "on"; },
        "on (default, as for a still): shading gradients from the gradient volume; off: the volume's taps")
        ->check(CLI::IsMember({"on", "off"}));
    command->add_option("--device", scene.device, "Vulkan device");
}

engine::RenderSettings settingsFor(const PinholeScene& scene, double stepVoxels) {
    engine::RenderSettings settings;
    settings.mode = scene.mode == "composite" ? engine::RenderMode::Composite : engine::RenderMode::IsoSurface;
    settings.isoHu = scene.isoHu;
    settings.transferFunction = scene.transferFunction;
    settings.gradient = engine::gradientFilterFromName(scene.gradient);
    settings.isUsingGradientVolume = scene.isUsingGradientVolume;
    settings.stepVoxels = stepVoxels;
    settings.isWritingHits = false;
    return settings;
}

engine::ViewRays raysFor(const PinholeScene& scene, double azimuthDeg) {
    const glm::dvec3 toEye = scene.positionMm - scene.lookAtMm;
    // The up direction made orthogonal to the view direction, as VTK's OrthogonalizeViewUp does.
    const glm::dvec3 axis = glm::normalize(scene.up - glm::dot(scene.up, toEye) / glm::dot(toEye, toEye) * toEye);
    engine::PinholeCamera camera;
    camera.positionMm = scene.lookAtMm + rotated(toEye, axis, glm::radians(azimuthDeg));
    camera.lookAtMm = scene.lookAtMm;
    camera.up = scene.up;
    camera.verticalFovDeg = scene.fovDeg;
    camera.width = camera.height = scene.size;
    return engine::viewRaysFrom(camera);
}

LoadedScene::LoadedScene(const PinholeScene& scene)
    : volume(volumes::loadVolume(scene.volumePath)),
      bricks(volumes::buildBrickMinMax(volume)),
      context(engine::GpuContextOptions{false, scene.device}),
      texture(context, volume),
      raycaster(context, volume, texture, bricks) {}

}  // namespace bench
