// cvc.render (a pinhole view) and cvc.render_display (every wall of a display, both eyes):
// images as numpy arrays, rendered with the GIL released on the process's one device, with the
// same settings `cvc render` uses for the same request.
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "engine/display/display.h"
#include "engine/display/display_json.h"
#include "engine/display/display_map.h"
#include "engine/render/pinhole_camera.h"
#include "engine/render/transfer_function.h"
#include "engine/sequence/camera_path.h"
#include "engine/sequence/frame_sequence.h"
#include "python/bindings.h"
#include "python/conversions.h"
#include "python/gpu_session.h"

namespace py = pybind11;

namespace cvc_python {
namespace {

/// What `cvc render`'s rendering options say, as keyword arguments: None keeps the use's default.
struct RenderKeywords {
    double iso = -500.0;
    std::string mode = "iso";
    std::string tf = "colon-wall";
    std::optional<double> step;
    std::string filter = "trilinear";
    std::optional<std::string> gradient;
    std::optional<bool> gradientVolume;
    std::optional<double> lightDistance;
    int refine = 2;
    bool skipping = true;
};

engine::RenderSettings settingsOf(const RenderKeywords& keywords, engine::RenderUse use, bool isWritingHits) {
    engine::RenderSettings settings = engine::defaultRenderSettings(use);
    if (keywords.mode != "iso" && keywords.mode != "composite") throw std::invalid_argument("mode must be iso or composite, not " + keywords.mode);
    if (keywords.filter != "trilinear" && keywords.filter != "tricubic") throw std::invalid_argument("filter must be trilinear or tricubic, not " + keywords.filter);
    settings.mode = keywords.mode == "composite" ? engine::RenderMode::Composite : engine::RenderMode::IsoSurface;
    settings.isoHu = keywords.iso;
    settings.transferFunction = keywords.tf;
    if (settings.mode == engine::RenderMode::Composite) engine::transferFunctionPreset(settings.transferFunction);
    settings.filter = keywords.filter == "tricubic" ? engine::VolumeFilter::Tricubic : engine::VolumeFilter::Trilinear;
    if (keywords.gradient) settings.gradient = engine::gradientFilterFromName(*keywords.gradient);
    if (keywords.gradientVolume) settings.isUsingGradientVolume = *keywords.gradientVolume;
    if (keywords.step) settings.stepVoxels = *keywords.step;
    if (keywords.lightDistance) settings.lightHalfDistanceMm = *keywords.lightDistance;
    settings.refinementSteps = keywords.refine;
    settings.isSkipping = keywords.skipping;
    settings.isWritingHits = isWritingHits;
    return settings;
}

/// The image as an (h, w, 4) uint8 array, and with hits an (h, w, 3) float32 array of first-hit
/// positions in volume millimetres, NaN where the ray missed.
py::object arraysOf(engine::RenderedImage image, bool withHits) {
    const auto height = static_cast<py::ssize_t>(image.height), width = static_cast<py::ssize_t>(image.width);
    py::array_t<uint8_t> rgba({height, width, py::ssize_t{4}});
    std::copy(image.rgba.begin(), image.rgba.end(), rgba.mutable_data());
    if (!withHits) return rgba;
    py::array_t<float> hits({height, width, py::ssize_t{3}});
    float* out = hits.mutable_data();
    for (std::size_t pixel = 0, n = static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height); pixel < n; ++pixel) {
        const bool isHit = image.hitMm[pixel * 4 + 3] > 0.5f;
        for (std::size_t axis = 0; axis < 3; ++axis) {
            out[pixel * 3 + axis] = isHit ? image.hitMm[pixel * 4 + axis] : std::numeric_limits<float>::quiet_NaN();
        }
    }
    return py::make_tuple(std::move(rgba), std::move(hits));
}

py::object render(SessionVolume& volume, const py::object& position, const py::object& lookAt, const py::object& up,
                  std::pair<int, int> size, double fov, bool hits, const RenderKeywords& keywords) {
    engine::PinholeCamera camera;
    camera.width = size.first;
    camera.height = size.second;
    camera.verticalFovDeg = fov;
    camera.positionMm = vec3Of(position, "position");
    camera.lookAtMm = vec3Of(lookAt, "look_at");
    camera.up = vec3Of(up, "up");
    const engine::RenderSettings settings = settingsOf(keywords, engine::RenderUse::Still, hits);
    engine::RenderedImage image;
    {
        py::gil_scoped_release release;
        image = volume.raycaster().render(engine::viewRaysFrom(camera), settings);
    }
    return arraysOf(std::move(image), hits);
}

py::dict renderDisplay(SessionVolume& volume, const std::string& displayName, const py::object& position,
                       const py::object& lookAt, const py::object& up, const std::string& path, int frame, int polyp,
                       double polypElevation, double polypAzimuth, double scale, const std::string& warp, int mapSize,
                       bool hits, const RenderKeywords& keywords) {
    engine::Display display = engine::loadDisplay(displayName);
    engine::validateDisplay(display);
    if (!(scale > 0.0 && scale <= 1000.0)) throw std::invalid_argument("scale must be in (0, 1000] mm per metre");
    // The pose as `cvc render --display` finds it: along a path (its frame-th, or the one viewing
    // a polyp of its ground truth), or the one given.
    engine::PoseRequest request;
    request.pathFile = path;
    request.polyp = polyp;
    request.polypElevationDeg = polypElevation;
    request.polypAzimuthDeg = polypAzimuth;
    if (!position.is_none()) request.positionMm = vec3Of(position, "position");
    if (!lookAt.is_none()) request.lookAtMm = vec3Of(lookAt, "look_at");
    if (!up.is_none()) request.up = vec3Of(up, "up");
    const std::vector<engine::CameraPose> poses = engine::posesFor(request);
    if (frame < 0 || frame >= static_cast<int>(poses.size())) {
        throw std::invalid_argument("frame " + std::to_string(frame) + " is not one of the " + std::to_string(poses.size()) + " poses");
    }
    const engine::CameraPose& pose = poses[static_cast<std::size_t>(frame)];
    const engine::WarpMode warpMode = engine::warpModeFromName(warp);
    const engine::RenderSettings settings = settingsOf(keywords, engine::RenderUse::DisplayFrames, hits);
    const std::vector<engine::Eye> eyes = {engine::Eye::Left, engine::Eye::Right};
    std::vector<engine::WallImage> walls;
    {
        py::gil_scoped_release release;
        engine::Raycaster& raycaster = volume.raycaster();
        const std::string key = display.map == conformal::MapKind::None ? std::string()
                                : engine::displayJson(display) + "@" + std::to_string(mapSize);
        if (!key.empty() && key != volume.cubeMapKey) {
            const conformal::CubeMap map = engine::cubeMapFor(display, mapSize, "");
            raycaster.setCubeMap(map.size, map.rgba);
            volume.cubeMapKey = key;
        }
        walls = engine::renderWalls(raycaster, display, engine::ScenePose{pose.positionMm, pose.forward, pose.up, scale},
                                    eyes, settings, warpMode);
    }
    py::dict byEye;
    for (engine::Eye eye : eyes) byEye[py::str(engine::eyeText(eye))] = py::dict();
    for (engine::WallImage& wall : walls) {
        byEye[py::str(engine::eyeText(wall.eye))][py::str(engine::wallNameText(wall.wall))] = arraysOf(std::move(wall.image), hits);
    }
    byEye["pose"] = py::dict(py::arg("position_mm") = py::make_tuple(pose.positionMm.x, pose.positionMm.y, pose.positionMm.z),
                             py::arg("forward") = py::make_tuple(pose.forward.x, pose.forward.y, pose.forward.z),
                             py::arg("up") = py::make_tuple(pose.up.x, pose.up.y, pose.up.z));
    return byEye;
}

}  // namespace

void addRenderBindings(py::module_& module) {
    module.def(
        "render",
        [](SessionVolume& volume, const py::object& position, const py::object& lookAt, const py::object& up,
           std::pair<int, int> size, double fov, double iso, bool hits, const std::string& mode, const std::string& tf,
           std::optional<double> step, const std::string& filter, std::optional<std::string> gradient,
           std::optional<bool> gradientVolume, std::optional<double> lightDistance, int refine, bool skipping) {
            RenderKeywords keywords{iso, mode, tf, step, filter, std::move(gradient), gradientVolume, lightDistance, refine, skipping};
            return render(volume, position, lookAt, up, size, fov, hits, keywords);
        },
        py::arg("volume"), py::arg("position"), py::arg("look_at"), py::arg("up"), py::arg("size") = std::pair<int, int>{1024, 1024},
        py::arg("fov") = 40.0, py::arg("iso") = -500.0, py::kw_only(), py::arg("hits") = false, py::arg("mode") = "iso",
        py::arg("tf") = "colon-wall", py::arg("step") = py::none(), py::arg("filter") = "trilinear",
        py::arg("gradient") = py::none(), py::arg("gradient_volume") = py::none(), py::arg("light_distance") = py::none(),
        py::arg("refine") = 2, py::arg("skipping") = true,
        "A pinhole view: an (h, w, 4) uint8 RGBA array; with hits=True also (h, w, 3) float32 first hits in volume mm "
        "(NaN where the ray missed). Positions are volume millimetres; the defaults are `cvc render`'s for a still.");
    module.def(
        "render_display",
        [](SessionVolume& volume, const std::string& display, const py::object& position, const py::object& lookAt,
           const py::object& up, const std::string& path, int frame, int polyp, double polypElevation, double polypAzimuth,
           double scale, const std::string& warp, int mapSize, bool hits, double iso, const std::string& mode,
           const std::string& tf, std::optional<double> step, std::optional<std::string> gradient,
           std::optional<bool> gradientVolume, std::optional<double> lightDistance) {
            RenderKeywords keywords{iso, mode, tf, step, "trilinear", std::move(gradient), gradientVolume, lightDistance, 2, true};
            return renderDisplay(volume, display, position, lookAt, up, path, frame, polyp, polypElevation, polypAzimuth,
                                 scale, warp, mapSize, hits, keywords);
        },
        py::arg("volume"), py::arg("display") = "ic5", py::kw_only(), py::arg("position") = py::none(),
        py::arg("look_at") = py::none(), py::arg("up") = py::none(), py::arg("path") = "", py::arg("frame") = 0,
        py::arg("polyp") = -1, py::arg("polyp_elevation") = 60.0, py::arg("polyp_azimuth") = 0.0, py::arg("scale") = 10.0,
        py::arg("warp") = "eye-centred", py::arg("map_size") = 1024, py::arg("hits") = false, py::arg("iso") = -500.0,
        py::arg("mode") = "iso", py::arg("tf") = "colon-wall", py::arg("step") = py::none(), py::arg("gradient") = py::none(),
        py::arg("gradient_volume") = py::none(), py::arg("light_distance") = py::none(),
        "Every wall of a display for both eyes at one pose, through its map: {'left': {'front': array, ...}, 'right': {...}, "
        "'pose': {...}}. The pose is the one `cvc render --display` takes for the same position/look_at/up, or path "
        "(its frame-th pose, or with polyp the one viewing that polyp of the path's ground truth).");
}

}  // namespace cvc_python
